#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "TestData.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/FrameSourceParameters.h"
#include "smap/io/InputPreset.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
/// The frame-source parameters `folder` is read with when no configuration is given.
io::FrameSourceParameters parametersFor(const std::string& folder)
{
    io::FrameSourceParameters p;
    if (const auto preset = io::presetForInput(folder))
    {
        core::TrackedConfig cfg;
        cfg.loadText(preset->text, preset->source);
        cfg.load(p);
        cfg.ensureAllKeysUsed();
    }
    return p;
}

/// Creates the folder `parent/name` holding one file, `file`, with `text`; returns its path.
std::string folderWith(const std::string& parent, const std::string& name, const std::string& file,
                       const std::string& text)
{
    std::string folder = parent + "/" + name;
    fs::create_directories(folder);
    std::ofstream(folder + "/" + file) << text;
    return folder;
}
}  // namespace

TEST(InputPreset, BuiltInPresetsAreTheConfigFilesAsBuilt)
{
    test::TempDir dir;
    const std::pair<const char*, const char*> cases[] = {
        {"rgbd_dataset_freiburg1_xyz", "tum_fr1.ini"},
        {"rgbd_dataset_freiburg2_pioneer_360", "tum_fr2.ini"},
        {"rgbd_dataset_freiburg3_walking_xyz_validation", "tum_fr3.ini"},
        {"7scenes-chess", "7scenes.ini"},
        {"rgbd_bonn_crowd2", "bonn.ini"}};
    for (const auto& [name, file] : cases)
    {
        fs::create_directories(dir / name);
        const auto preset = io::presetForInput(dir / name);
        ASSERT_TRUE(preset.has_value()) << name;
        EXPECT_EQ(preset->source, std::string("config/") + file);
        EXPECT_EQ(preset->text, test::readTextFile(test::sourceDir() + "/config/" + file))
            << file << " changed since the build: re-run cmake";
    }
    const auto fr3 = parametersFor(dir / "rgbd_dataset_freiburg3_walking_xyz_validation");
    ASSERT_TRUE(fr3.camera.has_value());
    EXPECT_EQ(fr3.camera->fx, 535.4);
    EXPECT_EQ(fr3.tum_depth_factor, 5000.0);
    const auto kitchen = parametersFor(dir / "7scenes-chess");
    ASSERT_TRUE(kitchen.camera.has_value());
    EXPECT_EQ(kitchen.camera->fx, 526.3);  // the colour camera
    ASSERT_TRUE(kitchen.depth_camera.has_value());
    EXPECT_EQ(kitchen.depth_camera->fx, 585.0);
    EXPECT_NEAR(kitchen.T_colour_depth.translation().x(), -0.025, 1e-12);
    EXPECT_TRUE(kitchen.T_colour_depth.linear().isIdentity(1e-12));
    EXPECT_EQ(kitchen.tum_depth_factor, 1000.0);
    const auto bonn = parametersFor(dir / "rgbd_bonn_crowd2");
    ASSERT_TRUE(bonn.camera.has_value());
    EXPECT_EQ(bonn.camera->fx, 542.822841);
    EXPECT_EQ(bonn.camera->distortion[0], 0.039903);
    EXPECT_EQ(bonn.camera->distortion[3], -0.000144);
    EXPECT_EQ(bonn.tum_depth_factor, 5000.0);
}

TEST(InputPreset, OnlyTheFolderItselfAndOnlyOneDatasetCount)
{
    test::TempDir dir;
    for (const char* name :
         {"RGBD_Dataset_Freiburg2_XYZ", "7_Scenes_office", "my-7-scenes", "freiburg1_vs_freiburg3",
          "rgbd_dataset_freiburg1_desk/kitchen", "plain"})
        fs::create_directories(dir / name);
    EXPECT_EQ(io::presetForInput(dir / "RGBD_Dataset_Freiburg2_XYZ")->source, "config/tum_fr2.ini");
    EXPECT_EQ(io::presetForInput(dir / "7_Scenes_office/")->source, "config/7scenes.ini");
    EXPECT_EQ(io::presetForInput(dir / "my-7-scenes")->source, "config/7scenes.ini");
    EXPECT_FALSE(io::presetForInput(dir / "freiburg1_vs_freiburg3").has_value());
    EXPECT_FALSE(io::presetForInput(dir / "rgbd_dataset_freiburg1_desk/kitchen").has_value());
    EXPECT_FALSE(io::presetForInput(dir / "plain").has_value());
    EXPECT_FALSE(io::presetForInput(dir / "rgbd_dataset_freiburg1_missing").has_value());
    EXPECT_FALSE(io::presetForInput("").has_value());
    std::ofstream(dir / "rgbd_dataset_freiburg1_file.rawlog") << "x";
    EXPECT_FALSE(io::presetForInput(dir / "rgbd_dataset_freiburg1_file.rawlog").has_value());
}

TEST(InputPreset, TheFoldersOwnCameraIniWinsOverItsName)
{
    test::TempDir dir;
    const std::string folder =
        folderWith(dir.str(), "rgbd_dataset_freiburg3_composited", "camera.ini",
                   "[camera]\nwidth = 320\nheight = 240\nfx = 262.5\nfy = 262.5\ncx = 159.5\ncy = "
                   "119.5\n[tum]\ndepth_factor = 5000\n");
    const auto preset = io::presetForInput(folder);
    ASSERT_TRUE(preset.has_value());
    EXPECT_EQ(preset->source, folder + "/camera.ini");
    const auto p = parametersFor(folder);
    ASSERT_TRUE(p.camera.has_value());
    EXPECT_EQ(p.camera->width, 320);
    EXPECT_EQ(p.camera->fx, 262.5);
}

TEST(InputPreset, AnOlderSmapSynthOutputIsNotTakenForItsSourceByName)
{
    // Composites written before smap-synth wrote camera.ini hold depth at 5000 units per metre
    // whatever they were made from: the 7-Scenes preset (1000) would read it five times too far.
    test::TempDir dir;
    const std::string old = folderWith(dir.str(), "7scenes-people-1000", "meta.json",
                                       "{\n  \"generator\": \"smap-synth\",\n  \"mode\": "
                                       "\"composite\",\n  \"depth_factor\": 5000\n}\n");
    EXPECT_TRUE(io::isSmapSynthOutput(old));
    EXPECT_FALSE(io::presetForInput(old).has_value());

    const std::string compact =
        folderWith(dir.str(), "7scenes-compact", "meta.json", R"({"generator":"smap-synth"})");
    EXPECT_TRUE(io::isSmapSynthOutput(compact));
    EXPECT_FALSE(io::presetForInput(compact).has_value());

    // Another tool's meta.json does not stop the name rule.
    const std::string other =
        folderWith(dir.str(), "7scenes-chess", "meta.json", R"({"generator": "something-else"})");
    EXPECT_FALSE(io::isSmapSynthOutput(other));
    ASSERT_TRUE(io::presetForInput(other).has_value());
    EXPECT_EQ(io::presetForInput(other)->source, "config/7scenes.ini");
}
