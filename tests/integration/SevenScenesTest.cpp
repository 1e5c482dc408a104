// Real data: the 7-Scenes kitchen read as a TUM folder and through tum2rawlog must give
// identical frames (acceptance: colour identical, depth registered to the colour camera
// identically: the rawlog keeps both cameras and their extrinsic).
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>

#include "CliHelpers.h"
#include "TestData.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/RawlogSource.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumToRawlogConverter.h"

using namespace smap;

TEST(SevenScenes, FolderAndConvertedRawlogGiveIdenticalFrames)
{
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    core::TrackedConfig cfg;
    cfg.loadFile(test::sourceDir() + "/config/7scenes.ini");
    io::FrameSourceParameters p;
    cfg.load(p);
    cfg.ensureAllKeysUsed();
    ASSERT_EQ(p.tum_depth_factor, 1000.0);

    test::TempDir dir;
    {
        io::TumSource folder(test::sevenScenesDir(), p);
        io::TumToRawlogConverter conv;
        conv.setMinLoggingLevel(mrpt::system::LVL_WARN);
        ASSERT_EQ(conv.convert(folder, p.tum_depth_factor, dir / "kitchen.rawlog").frames, 1000u);
    }
    io::TumSource folder(test::sevenScenesDir(), p);
    io::RawlogSource rawlog(dir / "kitchen.rawlog", {});
    size_t n = 0, colourDiffs = 0, depthDiffs = 0;
    while (auto a = folder.next())
    {
        auto b = rawlog.next();
        ASSERT_TRUE(b.has_value()) << "rawlog ended at frame " << n;
        colourDiffs += cv::norm(a->colour, b->colour, cv::NORM_INF) != 0.0;
        depthDiffs += cv::norm(a->depth, b->depth, cv::NORM_INF) != 0.0;
        ASSERT_EQ(a->camera, b->camera);
        ASSERT_NEAR(a->timestamp, b->timestamp, 1e-6);
        if (n == 0)
        {
            EXPECT_EQ(a->camera.fx, 526.3);  // the colour camera's
            // Registered without a rotation: z is kept, a whole number of millimetres.
            const float z = a->depth.at<float>(240, 320);
            ASSERT_GT(z, 0.0F);
            EXPECT_NEAR(z * 1000.0, std::round(z * 1000.0), 1e-3);
        }
        n++;
    }
    EXPECT_FALSE(rawlog.next().has_value());
    EXPECT_EQ(n, 1000u);
    EXPECT_EQ(colourDiffs, 0u);
    EXPECT_EQ(depthDiffs, 0u);
}

// Acceptance of the calibrated input: the raw folder through its shipped preset (the colour
// camera, depth registered to it) tracks every frame within 8 mm of the colour camera's SfM
// reference (measured 5.7 mm), and metrics.json reports both of the dataset's references
// (KinectFusion's groundtruth.txt, measured 49.7 mm, lies 49 mm from the SfM one).
TEST(SevenScenes, RawFolderTracksWithinEightMillimetresOfTheSfmReference)
{
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    test::TempDir dir;
    const test::CmdResult r = test::run(
        test::bin("semantic-mapper") + " " + test::sevenScenesDir() + " --out " + (dir / "out") +
        " --quiet --set segmentation.backend=none" + " --set output.snapshots=false");
    ASSERT_EQ(r.code, 0) << r.output;
    const std::string m = test::readTextFile(dir / "out/metrics.json");
    EXPECT_EQ(test::jsonNumber(m, {"tracking", "frames_with_pose"}), 1000.0) << m;
    // The folder's own reference first (groundtruth.txt), the other beside it after.
    EXPECT_NE(m.find("groundtruth.txt\""), std::string::npos) << m;
    const size_t other = m.find("\"other_references\"");
    ASSERT_NE(other, std::string::npos) << m;
    const std::string sfm = m.substr(other);
    ASSERT_NE(sfm.find("groundtruth_sfm.txt\""), std::string::npos) << sfm;
    EXPECT_LT(test::jsonNumber(sfm, {"ate", "rmse"}), 0.008) << sfm;
    const double kinectFusion = test::jsonNumber(m, {"evaluation", "ate", "rmse"});
    EXPECT_GT(kinectFusion, 0.03) << "the two references are 49 mm apart";
    EXPECT_LT(kinectFusion, 0.07);
}
