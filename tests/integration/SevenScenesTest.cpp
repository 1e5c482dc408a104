// Real data: the 7-Scenes kitchen read as a TUM folder and through tum2rawlog must give
// identical frames (acceptance: colour identical, depth identical to the source quantisation).
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>

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
            EXPECT_EQ(a->camera.fx, 585.0);
            // Raw millimetres: a valid pixel is a whole number of millimetres.
            const float z = a->depth.at<float>(240, 320);
            EXPECT_NEAR(z * 1000.0, std::round(z * 1000.0), 1e-3);
        }
        n++;
    }
    EXPECT_FALSE(rawlog.next().has_value());
    EXPECT_EQ(n, 1000u);
    EXPECT_EQ(colourDiffs, 0u);
    EXPECT_EQ(depthDiffs, 0u);
}
