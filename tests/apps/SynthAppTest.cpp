#include <gtest/gtest.h>
#include <mrpt/core/format.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "TestData.h"
#include "smap/apps/SynthApp.h"
#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/FrameSourceParameters.h"
#include "smap/io/InputPreset.h"
#include "smap/io/RawlogSource.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumTextFormats.h"

using namespace smap;
namespace fs = std::filesystem;

TEST(SynthApp, WritesTheTumLayoutWithGroundTruthAndARawlog)
{
    test::TempDir dir;
    std::ostringstream out;
    apps::SynthApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    ASSERT_EQ(app.run({"--preset", "walking_static", "--frames", "6", "--out", dir / "seq",
                       "--contact-sheet", "2"},
                      out),
              0);
    for (const char* f : {"rgb.txt", "depth.txt", "associations.txt", "groundtruth.txt",
                          "meta.json", "contact_sheet.png", "rgb/000005.png", "depth/000005.png",
                          "labels/000005.png", "instances/000005.png", "dynamic/000005.png",
                          "sequence.rawlog", "sequence_groundtruth.txt", "camera.ini"})
        EXPECT_TRUE(fs::exists(dir / ("seq/" + std::string(f)))) << f;
    EXPECT_EQ(io::readTumTrajectory(dir / "seq/groundtruth.txt").size(), 6u);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "seq/objects"), fs::directory_iterator()),
              2);  // two walkers
    const std::string meta = test::readTextFile(dir / "seq/meta.json");
    EXPECT_NE(meta.find("\"preset\": \"walking_static\""), std::string::npos) << meta;
    EXPECT_NE(meta.find("\"depth_factor\": 5000"), std::string::npos) << meta;
    // camera.ini says how to read the folder: the apps take it when no [camera] is given.
    const auto preset = io::presetForInput(dir / "seq");
    ASSERT_TRUE(preset.has_value());
    EXPECT_EQ(preset->source, dir / "seq/camera.ini");
    {
        core::TrackedConfig cfg;
        cfg.loadText(preset->text, preset->source);
        io::FrameSourceParameters p;
        cfg.load(p);
        cfg.ensureAllKeysUsed();
        ASSERT_TRUE(p.camera.has_value());
        EXPECT_EQ(p.camera->fx, 525.0);
        EXPECT_EQ(p.camera->width, 640);
        EXPECT_EQ(p.tum_depth_factor, 5000.0);
    }

    // The rawlog holds the same images as the folder.
    io::RawlogSource rawlog(dir / "seq/sequence.rawlog", {});
    size_t n = 0;
    while (auto f = rawlog.next())
    {
        const cv::Mat rgb = cv::imread(dir / ("seq/rgb/" + f->name + ".png"));
        EXPECT_EQ(cv::norm(rgb, f->colour, cv::NORM_INF), 0.0);
        EXPECT_EQ(f->camera.fx, 525.0);
        n++;
    }
    EXPECT_EQ(n, 6u);
}

TEST(SynthApp, RejectsBadArguments)
{
    test::TempDir dir;
    std::ostringstream out;
    apps::SynthApp app;
    EXPECT_THROW(app.run({"--preset", "nope", "--out", dir / "x"}, out), core::InputError);
    EXPECT_THROW(app.run({"--out", dir / "x"}, out), core::InputError);
    EXPECT_THROW(app.run({"--preset", "walking_xyz", "--out", dir / "x", "--frames", "0"}, out),
                 core::InputError);
    EXPECT_THROW(
        app.run({"--preset", "walking_xyz", "--out", dir / "x", "--distance-scale", "2"}, out),
        core::InputError);
    EXPECT_THROW(app.run({"--composite-onto", dir.str(), "--people", dir.str(), "--out", dir / "x",
                          "--distance-scale", "0"},
                         out),
                 core::InputError);
    EXPECT_FALSE(fs::exists(dir / "x"));
}

TEST(SynthApp, CompositesPeopleIntoTheRealKitchen)
{
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    SMAP_REQUIRE_DATA(test::sharedDir() + "/data/people");
    test::TempDir dir;
    std::ostringstream out;
    apps::SynthApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    const std::string sfm = test::sevenScenesDir() + "/groundtruth_sfm.txt";
    ASSERT_EQ(app.run({"--composite-onto", test::sevenScenesDir(), "--people",
                       test::sharedDir() + "/data/people", "--config",
                       test::sourceDir() + "/config/7scenes.ini", "--ground-truth", sfm, "--frames",
                       "20", "--out", dir / "comp", "--no-rawlog", "--contact-sheet", "0"},
                      out),
              0);
    EXPECT_NE(test::readTextFile(dir / "comp/meta.json").find("\"mode\": \"composite\""),
              std::string::npos);
    // The composite's ground truth is the colour camera's poses it was made with.
    const auto written = io::readTumTrajectory(dir / "comp/groundtruth.txt");
    const auto colourPoses = io::readTumTrajectory(sfm);
    ASSERT_EQ(written.size(), 20u);
    for (size_t i = 0; i < written.size(); i++)
        EXPECT_LT((written[i].T_world_cam.translation() - colourPoses[i].T_world_cam.translation())
                      .norm(),
                  1e-6);
    // The frames are the colour camera's: depth registered by the preset's [depth_camera], as
    // semantic-mapper reads the folder.
    core::TrackedConfig cfg;
    cfg.loadFile(test::sourceDir() + "/config/7scenes.ini");
    io::FrameSourceParameters params;
    cfg.load(params);
    io::TumSource kitchen(test::sevenScenesDir(), params);
    size_t framesWithPeople = 0, unchanged = 0, compared = 0;
    for (int i = 0; i < 20; i++)
    {
        const std::string n = mrpt::format("%06d.png", i);
        const cv::Mat labels = cv::imread(dir / ("comp/labels/" + n), cv::IMREAD_UNCHANGED);
        const cv::Mat depth = cv::imread(dir / ("comp/depth/" + n), cv::IMREAD_UNCHANGED);
        const auto source = kitchen.next();
        ASSERT_TRUE(source.has_value());
        framesWithPeople += cv::countNonZero(labels == 15) > 0;
        // Away from people the real (registered) depth is kept, to the 0.2 mm of the output's
        // 5000 units per metre.
        for (int v = 0; v < depth.rows; v += 7)
            for (int u = 0; u < depth.cols; u += 7)
                if (labels.at<uint8_t>(v, u) == 255)
                {
                    compared++;
                    unchanged += std::abs(depth.at<uint16_t>(v, u) / 5000.0 -
                                          source->depth.at<float>(v, u)) <= 1.0 / 5000.0;
                }
    }
    EXPECT_GT(framesWithPeople, 10u);
    EXPECT_GT(compared, 1000u);
    EXPECT_EQ(unchanged, compared);
}
