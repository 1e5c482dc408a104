#include <gtest/gtest.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/pipeline/SemanticMapperApp.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
size_t countLines(const std::string& path)
{
    const std::string s = smap::test::readTextFile(path);
    return static_cast<size_t>(std::count(s.begin(), s.end(), '\n'));
}
std::string smallCameraIni()
{
    return "[camera]\nwidth = 64\nheight = 48\nfx = 60\nfy = 60\ncx = 31.5\ncy = 23.5\n";
}
}  // namespace

TEST(SemanticMapperApp, RunsOnTheEmbeddedDefaultRecording)
{
    SMAP_REQUIRE_DATA(pipeline::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    std::ostringstream out;
    pipeline::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    EXPECT_EQ(app.run({"--out", dir / "o"}, out), 0);
    // The project's sample: 200 frames of synthetic walking_xyz at 320x240 (fx 262.5).
    EXPECT_EQ(app.result().frames, 200u);
    const std::string summary = smap::test::readTextFile(dir / "o/summary.json");
    EXPECT_NE(summary.find("\"frames\": 200"), std::string::npos) << summary;
    EXPECT_NE(summary.find("\"fx\": 262.5"), std::string::npos) << summary;
    EXPECT_NE(summary.find("sample_walking_xyz_groundtruth.txt"), std::string::npos) << summary;
    EXPECT_EQ(countLines(dir / "o/frames.csv"), 201u);
    // Tracking: one TUM line per frame with a pose (2 comment lines), the first at the world
    // origin, and the keyframe trajectory.
    const std::string traj = smap::test::readTextFile(dir / "o/trajectory.txt");
    const size_t withPose = countLines(dir / "o/trajectory.txt") - 2;
    EXPECT_GE(withPose, 190u);
    EXPECT_NE(summary.find("\"frames_with_pose\": " + std::to_string(withPose)), std::string::npos)
        << summary;
    {
        std::istringstream lines(traj);
        std::string line;
        while (std::getline(lines, line) && line[0] == '#')
        {
        }
        std::istringstream first(line);
        double t = 0, x = 1, y = 1, z = 1, qx = 1, qy = 1, qz = 1, qw = 0;
        first >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
        // The dynamic filter (on by default) has no evidence on the first frame, so the map
        // starts on the second one (30 Hz).
        EXPECT_NEAR(t, 1.0e9 + 1.0 / 30.0, 1e-5);
        EXPECT_NEAR(std::abs(x) + std::abs(y) + std::abs(z), 0.0, 1e-12) << line;
        EXPECT_NEAR(std::abs(qx) + std::abs(qy) + std::abs(qz), 0.0, 1e-12) << line;
    }
    EXPECT_GE(countLines(dir / "o/keyframes.txt"), 2u + 3u);
    const std::string csv = smap::test::readTextFile(dir / "o/frames.csv");
    EXPECT_NE(csv.find(",status,keypoints,inliers,keyframe,extraction_ms"), std::string::npos);
    EXPECT_NE(csv.find(",initialised,"), std::string::npos);
    EXPECT_NE(csv.find("\n0,1000000000.000000,"), std::string::npos);
    EXPECT_NE(csv.substr(0, csv.find("\n1,")).find(",not_initialised,"), std::string::npos)
        << "frame 0: no dynamic evidence yet";
    EXPECT_TRUE(fs::exists(dir / "o/config-effective.ini"));
    EXPECT_NE(out.str().find("outputs in"), std::string::npos);
}

// The paper-mode dynamic filter reaches tracking: on the sample (people walking through the
// view) some keypoints of every frame after the first are marked dynamic; with it off, none.
TEST(SemanticMapperApp, DynamicFilterModeMarksKeypointsOfWalkingPeople)
{
    SMAP_REQUIRE_DATA(pipeline::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    for (const std::string mode : {"paper", "off"})
    {
        std::ostringstream out;
        pipeline::SemanticMapperApp app;
        app.setMinLoggingLevel(mrpt::system::LVL_WARN);
        ASSERT_EQ(app.run({"--out", dir / mode, "--set", "input.max_frames=30", "--set",
                           "dynamic.mode=" + mode},
                          out),
                  0);
        std::istringstream csv(smap::test::readTextFile(dir / (mode + "/frames.csv")));
        std::string line, header;
        std::getline(csv, header);
        // dynamic_keypoints is the 5th column from the end.
        size_t total = 0, frames = 0;
        while (std::getline(csv, line))
        {
            std::vector<std::string> cols;
            std::stringstream ss(line);
            for (std::string c; std::getline(ss, c, ',');)
                cols.push_back(c);
            ASSERT_GE(cols.size(), 5U);
            total += std::stoul(cols[cols.size() - 5]);
            frames++;
        }
        EXPECT_EQ(frames, 30U);
        if (mode == "paper")
            EXPECT_GT(total, 29U * 5U) << "about a tenth of the keypoints are on people";
        else
            EXPECT_EQ(total, 0U);
    }
}

TEST(SemanticMapperApp, DynamicDebugWritesFigureAndEvidenceForChosenFrames)
{
    SMAP_REQUIRE_DATA(pipeline::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    std::ostringstream out;
    pipeline::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    ASSERT_EQ(
        app.run({"--out", dir / "o", "--set", "input.max_frames=8", "--dynamic-debug", "0,5-6"},
                out),
        0);
    for (int i = 0; i < 8; ++i)
    {
        const bool chosen = i == 0 || i == 5 || i == 6;
        const std::string stem = dir / mrpt::format("o/dynamic/%06d", i);
        EXPECT_EQ(fs::exists(stem + ".png"), chosen) << i;
        EXPECT_EQ(fs::exists(stem + ".csv"), chosen) << i;
    }
    EXPECT_EQ(test::readTextFile(dir / "o/dynamic/000000.csv").rfind("# not evaluated", 0), 0U);
    // Frame 5's table: one row per keypoint, and as many dynamic rows as frames.csv counts.
    std::istringstream table(test::readTextFile(dir / "o/dynamic/000005.csv"));
    std::string line;
    std::getline(table, line);
    ASSERT_EQ(line.rfind("u,v,", 0), 0U) << line;
    size_t rows = 0, dynamicRows = 0;
    while (std::getline(table, line))
    {
        rows++;
        dynamicRows += line.back() == '1' ? 1 : 0;
    }
    std::istringstream csv(test::readTextFile(dir / "o/frames.csv"));
    std::string header;
    std::getline(csv, header);
    for (int i = 0; i <= 5; ++i)
        std::getline(csv, line);
    std::vector<std::string> cols;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');)
        cols.push_back(c);
    ASSERT_GE(cols.size(), 10U);
    EXPECT_EQ(cols[0], "5");
    EXPECT_EQ(dynamicRows, std::stoul(cols[cols.size() - 5]));
    EXPECT_EQ(rows, std::stoul(cols[9])) << "keypoints column";
    EXPECT_GT(dynamicRows, 0U) << "the sample has people walking";
    const cv::Mat picture = cv::imread(dir / "o/dynamic/000005.png");
    EXPECT_EQ(picture.cols, 320);

    EXPECT_THROW(app.run({"--out", dir / "p", "--dynamic-debug", "5-2"}, out), core::InputError);
    EXPECT_THROW(app.run({"--out", dir / "p", "--dynamic-debug", "x"}, out), core::InputError);
}

TEST(SemanticMapperApp, ConfigAndOverridesReachTheSource)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 6, 0.0, false);
    std::ofstream(dir / "cam.ini") << smallCameraIni() << "[tum]\ndepth_factor = 1000\n";
    std::ostringstream out;
    pipeline::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    EXPECT_EQ(app.run({dir / "tum", "--config", dir / "cam.ini", "--out", dir / "o", "--set",
                       "input.stride=2"},
                      out),
              0);
    EXPECT_EQ(app.result().frames, 3u);
    const std::string eff = smap::test::readTextFile(dir / "o/config-effective.ini");
    EXPECT_NE(eff.find("stride = 2"), std::string::npos) << eff;
    EXPECT_NE(eff.find("depth_factor = 1000"), std::string::npos) << eff;
    // Depth factor 1000: the first frame's minimum depth is its smallest raw value / 1000.
    const std::string csv = smap::test::readTextFile(dir / "o/frames.csv");
    EXPECT_NE(csv.find("0,100.000000,f0,"), std::string::npos) << csv;
}

TEST(SemanticMapperApp, UnknownConfigKeyAndBadInputAreInputErrors)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 2, 0.0, false);
    std::ofstream(dir / "bad.ini") << smallCameraIni() << "[tum]\ndepth_facter = 1000\n";
    std::ostringstream out;
    pipeline::SemanticMapperApp app;
    try
    {
        app.run({dir / "tum", "--config", dir / "bad.ini", "--out", dir / "o"}, out);
        FAIL();
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("depth_facter"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bad.ini"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "o"));  // nothing written for a rejected configuration
    EXPECT_THROW(app.run({dir / "nope", "--out", dir / "o"}, out), core::InputError);
    EXPECT_THROW(app.run({"a", "b"}, out), core::InputError);
    EXPECT_EQ(app.run({"--help"}, out), 0);
    EXPECT_NE(out.str().find("Usage: semantic-mapper"), std::string::npos);
}
