// Offscreen snapshots of both maps against golden images (tolerance for Mesa versions), and
// the legend. SMAP_UPDATE_GOLDEN=1 rewrites the golden images (look at them before committing).
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "TestData.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"
#include "smap/maps/MapSnapshot.h"

using namespace smap;

namespace
{
/// A tilted camera seeing a floor (chair class on the left, person on the right) at 1-3 m.
maps::CObservationSemanticRGBD::Ptr scene()
{
    auto o = maps::CObservationSemanticRGBD::Create();
    o->camera.width = 80;
    o->camera.height = 60;
    o->camera.fx = o->camera.fy = 60.0;
    o->camera.cx = 39.5;
    o->camera.cy = 29.5;
    o->colour = cv::Mat(60, 80, CV_8UC3, cv::Scalar(40, 160, 220));
    o->depth = cv::Mat(60, 80, CV_32FC1);
    for (int v = 0; v < 60; v++)
        o->depth.row(v).setTo(1.0f + 2.0f * static_cast<float>(59 - v) / 59.0f);
    o->labels = cv::Mat(60, 80, CV_8UC1, cv::Scalar(9));
    o->labels(cv::Rect(40, 0, 40, 60)).setTo(15);
    o->confidence = cv::Mat(60, 80, CV_32FC1, cv::Scalar(0.9f));
    return o;
}

void compareWithGolden(const cv::Mat& image, const std::string& name)
{
    const std::string path = test::sourceDir() + "/tests/maps/golden/" + name;
    const char* update = std::getenv("SMAP_UPDATE_GOLDEN");
    if (update && std::string(update) == "1")
    {
        cv::imwrite(path, image);
        GTEST_SKIP() << "golden image rewritten: " << path;
    }
    const cv::Mat golden = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(golden.empty()) << "missing golden image " << path;
    ASSERT_EQ(golden.size(), image.size());
    cv::Mat diff;
    cv::absdiff(golden, image, diff);
    const double mean = cv::mean(diff)[0] + cv::mean(diff)[1] + cv::mean(diff)[2];
    cv::Mat grey;
    cv::cvtColor(diff, grey, cv::COLOR_BGR2GRAY);
    const double changed = cv::countNonZero(grey > 40) / static_cast<double>(grey.total());
    EXPECT_LT(mean / 3.0, 3.0) << name;
    EXPECT_LT(changed, 0.02) << name;
}
}  // namespace

TEST(MapSnapshot, PointsMapByClassWithLegendMatchesGolden)
{
    maps::CSemanticPointsMap map;
    map.insertionOptions.voxel_size = 0.05;
    map.insertObservation(*scene(), mrpt::poses::CPose3D(0, 0, 1.5, 0, 0, -2.0));
    maps::SnapshotOptions o;
    o.width = 320;
    o.height = 240;
    const cv::Mat image = maps::MapSnapshot(o).render(map);
    ASSERT_EQ(image.type(), CV_8UC3);
    // Not blank: both class colours are on the picture.
    const auto voc = core::LabelSet::pascalVoc();
    const cv::Vec3b chair = voc[9].colourBgr, person = voc[15].colourBgr;
    int chairPixels = 0, personPixels = 0;
    for (int v = 0; v < image.rows; v++)
        for (int u = 60; u < image.cols; u++)  // right of the legend
        {
            chairPixels += image.at<cv::Vec3b>(v, u) == chair;
            personPixels += image.at<cv::Vec3b>(v, u) == person;
        }
    EXPECT_GT(chairPixels, 200);
    EXPECT_GT(personPixels, 200);
    compareWithGolden(image, "points_by_class.png");
}

TEST(MapSnapshot, OctoMapByRgbMatchesGolden)
{
    maps::CSemanticOctoMap map;
    map.renderOptions.colour_by_class = false;
    map.insertObservation(*scene(), mrpt::poses::CPose3D(0, 0, 1.5, 0, 0, -2.0));
    maps::SnapshotOptions o;
    o.width = 320;
    o.height = 240;
    const cv::Mat image = maps::MapSnapshot(o).render(map);
    compareWithGolden(image, "octomap_by_rgb.png");
}
