// The committed sample recording (rawlogs/, made by scripts/make-sample.sh) is complete and
// consistent with its ground truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "TestData.h"
#include "smap/core/TimestampAssociation.h"
#include "smap/io/RawlogSource.h"
#include "smap/io/TumTextFormats.h"

using namespace smap;

TEST(SampleRecording, RawlogFramesMatchGroundTruthAndLabels)
{
    const std::string base = test::sourceDir() + "/rawlogs/sample_walking_xyz";
    ASSERT_TRUE(std::filesystem::exists(base + ".rawlog"));
    io::RawlogSource src(base + ".rawlog", {});
    EXPECT_EQ(src.groundTruthPath(), base + "_groundtruth.txt");
    const auto gt = io::readTumTrajectory(src.groundTruthPath());
    std::vector<double> tFrames, tGt;
    for (const auto& p : gt)
        tGt.push_back(p.timestamp);
    size_t n = 0, withPeople = 0;
    while (auto f = src.next())
    {
        ASSERT_EQ(f->colour.cols, 320);
        ASSERT_EQ(f->camera.fx, 262.5);
        ASSERT_GT(f->validDepthFraction(), 0.8);
        tFrames.push_back(f->timestamp);
        const cv::Mat labels =
            cv::imread(base + "_gt/labels/" + f->name + ".png", cv::IMREAD_UNCHANGED);
        const cv::Mat dynamic =
            cv::imread(base + "_gt/dynamic/" + f->name + ".png", cv::IMREAD_UNCHANGED);
        ASSERT_EQ(labels.size(), f->colour.size()) << f->name;
        ASSERT_EQ(cv::countNonZero((dynamic != 0) != (labels == 15)), 0) << f->name;  // walkers
        withPeople += cv::countNonZero(labels == 15) > 0;
        n++;
    }
    EXPECT_EQ(n, 200u);
    EXPECT_EQ(core::associateTimestamps(tFrames, tGt, 0.001).size(), 200u);
    EXPECT_GT(withPeople, 100u);  // people are in view most of the time
}
