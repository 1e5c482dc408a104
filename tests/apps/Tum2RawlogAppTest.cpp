#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/apps/Tum2RawlogApp.h"
#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/InputPreset.h"
#include "smap/io/RawlogSource.h"
#include "smap/io/TumSource.h"

using namespace smap;

TEST(Tum2RawlogApp, ConvertsWithConfiguredCamera)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 3, 0.0, false);
    std::ofstream(dir / "cam.ini")
        << "[camera]\nwidth = 64\nheight = 48\nfx = 60\nfy = 60\ncx = 31.5\ncy = 23.5\n";
    std::ostringstream out;
    apps::Tum2RawlogApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    EXPECT_EQ(
        app.run({dir / "tum", dir / "x.rawlog", "--config", dir / "cam.ini", "--max-frames", "2"},
                out),
        0);
    EXPECT_NE(out.str().find("2 frames"), std::string::npos) << out.str();
    EXPECT_TRUE(std::filesystem::exists(dir / "x_groundtruth.txt"));
    EXPECT_THROW(app.run({dir / "tum"}, out), core::InputError);
    EXPECT_THROW(app.run({dir / "tum", dir / "y.rawlog", "--max-frames", "-1"}, out),
                 core::InputError);
}

TEST(Tum2RawlogApp, FolderWithoutCameraUsesItsOwnCameraIniOrThePresetItsNameSays)
{
    test::TempDir dir;
    std::ostringstream out;
    apps::Tum2RawlogApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    const auto convertFirst = [&](const std::string& folder, std::vector<std::string> extra = {})
    {
        std::vector<std::string> args{folder, dir / "out.rawlog", "--max-frames", "1"};
        args.insert(args.end(), extra.begin(), extra.end());
        EXPECT_EQ(app.run(args, out), 0) << folder;
        io::RawlogSource src(dir / "out.rawlog", {});
        auto f = src.next();
        EXPECT_TRUE(f.has_value());
        return f.value_or(core::RgbdFrame{});
    };
    // Depth of pixel (10, 20) of test frame 0, in metres, at a depth factor.
    const auto depthAt = [](const core::RgbdFrame& f) { return f.depth.at<float>(10, 20); };
    const auto expectedDepth = [](int w, int h, double factor)
    { return test::patternDepthRaw(w, h, 0).at<uint16_t>(10, 20) / factor; };

    // 64x48 images: the default Kinect camera (640x480) cannot read them, the folder's own
    // camera.ini can (with its depth factor).
    test::writeTumFolder(dir / "small", 1, 0.0, false);
    EXPECT_THROW(app.run({dir / "small", dir / "out.rawlog"}, out), core::InputError);
    std::ofstream(dir / "small/camera.ini")
        << "[camera]\nwidth = 64\nheight = 48\nfx = 60\nfy = 61\ncx = 31.5\ncy = 23.5\n"
           "[tum]\ndepth_factor = 1000\n";
    auto f = convertFirst(dir / "small");
    EXPECT_EQ(f.camera.fy, 61.0);
    EXPECT_NEAR(depthAt(f), expectedDepth(64, 48, 1000.0), 1e-3);

    // Named after a dataset: its preset, under what the user gives.
    test::writeTumFolder(dir / "rgbd_dataset_freiburg1_desk", 1, 0.0, false, 640, 480);
    f = convertFirst(dir / "rgbd_dataset_freiburg1_desk");
    EXPECT_EQ(f.camera.fx, 517.3);
    EXPECT_EQ(f.camera.distortion[0], 0.2624);
    EXPECT_NEAR(depthAt(f), expectedDepth(640, 480, 5000.0), 1e-3);
    test::writeTumFolder(dir / "7scenes-office", 1, 0.0, false, 640, 480);
    f = convertFirst(dir / "7scenes-office");
    // 7-Scenes: the colour camera, depth registered to it from the 585 px depth camera, in
    // millimetres; read back it is the folder read with the same preset.
    EXPECT_EQ(f.camera.fx, 526.3);
    const auto sevenScenesFrame = [&](double factor)
    {
        core::TrackedConfig cfg;
        const auto preset = io::presetForInput(dir / "7scenes-office");
        cfg.loadText(preset->text, preset->source);
        io::FrameSourceParameters p;
        cfg.load(p);
        p.tum_depth_factor = factor;
        io::TumSource folder(dir / "7scenes-office", p);
        return folder.next().value();
    };
    EXPECT_EQ(cv::norm(f.depth, sevenScenesFrame(1000.0).depth, cv::NORM_INF), 0.0);
    // The pattern's 5000 - 33912 raw units as millimetres (5 - 34 m), then at 5000 per metre.
    EXPECT_GT(cv::mean(f.depth, f.depth > 0.0F)[0], 10.0);
    f = convertFirst(dir / "7scenes-office", {"--set", "tum.depth_factor=5000"});
    EXPECT_EQ(cv::norm(f.depth, sevenScenesFrame(5000.0).depth, cv::NORM_INF), 0.0);
    EXPECT_LT(cv::mean(f.depth, f.depth > 0.0F)[0], 7.0);

    // A [camera] of the user's replaces the preset whole (no distortion inherited from it).
    std::ofstream(dir / "cam640.ini")
        << "[camera]\nwidth = 640\nheight = 480\nfx = 500\nfy = 500\ncx = 319.5\ncy = 239.5\n";
    f = convertFirst(dir / "rgbd_dataset_freiburg1_desk", {"--config", dir / "cam640.ini"});
    EXPECT_EQ(f.camera.fx, 500.0);
    EXPECT_FALSE(f.camera.hasDistortion());
}
