#include <gtest/gtest.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/apps/SemanticMapperApp.h"
#include "smap/core/InputError.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/maps/CSemanticPointsMap.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
/// The index of column `name` in a CSV header line (fails the test when absent).
size_t columnOf(const std::string& header, const std::string& name)
{
    std::stringstream ss(header);
    size_t i = 0;
    for (std::string c; std::getline(ss, c, ','); ++i)
        if (c == name)
            return i;
    ADD_FAILURE() << "no column " << name << " in " << header;
    return 0;
}
}  // namespace

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

/// Runs semantic-mapper with `args`, logging warnings only; its exit code.
int runQuietly(const std::vector<std::string>& args)
{
    std::ostringstream out;
    apps::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    return app.run(args, out);
}

// Fast settings for tests that check the wiring rather than segmentation quality.
std::vector<std::string> fast(std::vector<std::string> args)
{
    for (const char* s : {"segmentation.backend=none", "output.snapshots=false"})
    {
        args.emplace_back("--set");
        args.emplace_back(s);
    }
    return args;
}

std::vector<uint8_t> readBytes(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST(SemanticMapperApp, RunsOnTheEmbeddedDefaultRecording)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    std::ostringstream out;
    apps::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    EXPECT_EQ(app.run(fast({"--out", dir / "o"}), out), 0);
    // The project's sample: 200 frames of synthetic walking_xyz at 320x240 (fx 262.5).
    EXPECT_EQ(app.result().frames, 200u);
    const std::string metrics = smap::test::readTextFile(dir / "o/metrics.json");
    EXPECT_NE(metrics.find("\"frames\": 200"), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("\"fx\": 262.5"), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("sample_walking_xyz_groundtruth.txt"), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("\"ate\""), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("\"interrupted\": false"), std::string::npos) << metrics;
    EXPECT_EQ(countLines(dir / "o/frames.csv"), 201u);
    // Tracking: one TUM line per frame with a pose (2 comment lines), and the keyframe
    // trajectory.
    const std::string traj = smap::test::readTextFile(dir / "o/trajectory.txt");
    const size_t withPose = countLines(dir / "o/trajectory.txt") - 2;
    EXPECT_GE(withPose, 190u);
    EXPECT_NE(metrics.find("\"frames_with_pose\": " + std::to_string(withPose)), std::string::npos)
        << metrics;
    {
        std::istringstream lines(traj);
        std::string line;
        while (std::getline(lines, line) && line[0] == '#')
        {
        }
        // The dynamic filter (on by default) has no evidence on the first frame, so the map
        // starts on the second one (30 Hz), at the world origin; the filter's ego-motion then
        // places the first frame, a few millimetres away at this walking speed.
        double t = 0, x = 1, y = 1, z = 1, qx = 1, qy = 1, qz = 1, qw = 0;
        std::istringstream(line) >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
        EXPECT_NEAR(t, 1.0e9, 1e-5) << line;
        const double step = std::sqrt(x * x + y * y + z * z);
        EXPECT_GT(step, 1e-4) << line;
        EXPECT_LT(step, 0.05) << line;
        ASSERT_TRUE(std::getline(lines, line));
        std::istringstream(line) >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
        EXPECT_NEAR(t, 1.0e9 + 1.0 / 30.0, 1e-5);
        EXPECT_NEAR(std::abs(x) + std::abs(y) + std::abs(z), 0.0, 1e-12) << line;
        EXPECT_NEAR(std::abs(qx) + std::abs(qy) + std::abs(qz), 0.0, 1e-12) << line;
    }
    EXPECT_GE(countLines(dir / "o/keyframes.txt"), 2u + 3u);
    const std::string csv = smap::test::readTextFile(dir / "o/frames.csv");
    EXPECT_NE(csv.find(",status,keypoints,inliers,keyframe,extraction_ms"), std::string::npos);
    EXPECT_NE(csv.find(",initialised,"), std::string::npos);
    EXPECT_NE(csv.find("\n0,1000000000.000000,"), std::string::npos);
    EXPECT_NE(csv.substr(0, csv.find("\n1,")).find(",odometry,"), std::string::npos)
        << "frame 0: no dynamic evidence yet, posed when the map started";
    // Every keyframe tracking made reached the maps (when_full = wait), and the map files and
    // the annotated rawlog exist.
    EXPECT_GT(app.result().keyframes, 3u);
    EXPECT_NE(metrics.find("\"mapped\": " + std::to_string(app.result().keyframes)),
              std::string::npos);
    EXPECT_NE(metrics.find("\"submitted\": " + std::to_string(app.result().keyframes)),
              std::string::npos);
    for (const char* f :
         {"config-effective.ini", "semantic_points.ply", "semantic_octomap.ot",
          "semantic_octomap.bt", "semantic_map.bin", "semantic_map.3Dscene", "annotated.rawlog"})
        EXPECT_TRUE(fs::exists(dir / (std::string("o/") + f))) << f;
    EXPECT_FALSE(fs::exists(dir / "o/snapshots/map_by_class.png")) << "output.snapshots=false";
    EXPECT_NE(out.str().find("outputs in"), std::string::npos);
    // No temporary files left behind.
    for (const auto& e : fs::directory_iterator(dir / "o"))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

// The .3Dscene output is what MRPT's SceneViewer3D opens: MRPT reads it back with the point map's
// every point (as many as semantic_points.ply holds) and the trajectory's every step, the first
// step's line starting at the first pose of trajectory.txt.
TEST(SemanticMapperApp, SceneFileLoadsInMrptWithTheMapAndTheTrajectory)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    ASSERT_EQ(runQuietly(fast({"--out", dir / "o", "--set", "input.max_frames=40"})), 0);
    mrpt::opengl::COpenGLScene scene;
    ASSERT_TRUE(scene.loadFromFile(dir / "o/semantic_map.3Dscene"));
    auto world = scene.getByClass<mrpt::opengl::CSetOfObjects>();
    ASSERT_TRUE(world);
    EXPECT_EQ(world->getName(), "world");
    auto points = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(
        world->getByName("semantic_points"));
    auto voxels = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(
        world->getByName("semantic_octomap"));
    auto path =
        std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(world->getByName("trajectory"));
    ASSERT_TRUE(points && voxels && path);
    const std::string ply = smap::test::readTextFile(dir / "o/semantic_points.ply");
    const size_t at = ply.find("element vertex ");
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(points->size(), std::stoul(ply.substr(at + 15)));
    EXPECT_GT(points->size(), 1000U);
    EXPECT_GT(voxels->size(), 100U);

    std::vector<std::array<double, 3>> poses;
    std::istringstream lines(smap::test::readTextFile(dir / "o/trajectory.txt"));
    for (std::string line; std::getline(lines, line);)
        if (!line.empty() && line[0] != '#')
        {
            double t = 0, x = 0, y = 0, z = 0;
            std::istringstream(line) >> t >> x >> y >> z;
            poses.push_back({x, y, z});
        }
    ASSERT_GT(poses.size(), 30U);
    EXPECT_EQ(path->getLineCount(), poses.size() - 1);
    double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
    path->getLineByIndex(0, x0, y0, z0, x1, y1, z1);
    EXPECT_NEAR(x0, poses[0][0], 1e-6);
    EXPECT_NEAR(y0, poses[0][1], 1e-6);
    EXPECT_NEAR(z0, poses[0][2], 1e-6);
    EXPECT_NEAR(z1, poses[1][2], 1e-6);
}

// Acceptance: the same input and configuration twice give byte-identical trajectory and maps.
TEST(SemanticMapperApp, SameInputAndConfigurationGiveIdenticalFiles)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    for (const std::string run : {"a", "b"})
        ASSERT_EQ(runQuietly(fast({"--out", dir / run, "--set", "input.max_frames=80"})), 0);
    for (const char* f :
         {"trajectory.txt", "keyframes.txt", "semantic_points.ply", "semantic_octomap.ot",
          "semantic_octomap.bt", "semantic_map.bin", "annotated.rawlog"})
    {
        const auto a = readBytes(dir / (std::string("a/") + f));
        EXPECT_FALSE(a.empty()) << f;
        EXPECT_TRUE(a == readBytes(dir / (std::string("b/") + f)))
            << f << " differs between two runs";
    }
}

// The paper-mode dynamic filter reaches tracking: on the sample (people walking through the
// view) some keypoints of every frame after the first are marked dynamic; with it off, none.
TEST(SemanticMapperApp, DynamicFilterModeMarksKeypointsOfWalkingPeople)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    for (const std::string mode : {"paper", "off"})
    {
        std::ostringstream out;
        apps::SemanticMapperApp app;
        app.setMinLoggingLevel(mrpt::system::LVL_WARN);
        ASSERT_EQ(app.run(fast({"--out", dir / mode, "--set", "input.max_frames=30", "--set",
                                "dynamic.mode=" + mode}),
                          out),
                  0);
        std::istringstream csv(smap::test::readTextFile(dir / (mode + "/frames.csv")));
        std::string line, header;
        std::getline(csv, header);
        const size_t dynamicColumn = columnOf(header, "dynamic_keypoints");
        size_t total = 0, frames = 0;
        while (std::getline(csv, line))
        {
            std::vector<std::string> cols;
            std::stringstream ss(line);
            for (std::string c; std::getline(ss, c, ',');)
                cols.push_back(c);
            ASSERT_GT(cols.size(), dynamicColumn);
            total += std::stoul(cols[dynamicColumn]);
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
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    std::ostringstream out;
    apps::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    ASSERT_EQ(app.run(fast({"--out", dir / "o", "--set", "input.max_frames=8", "--dynamic-debug",
                            "0,5-6"}),
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
    ASSERT_GT(cols.size(), columnOf(header, "dynamic_keypoints"));
    EXPECT_EQ(cols[0], "5");
    EXPECT_EQ(dynamicRows, std::stoul(cols[columnOf(header, "dynamic_keypoints")]));
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
    apps::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    EXPECT_EQ(app.run(fast({dir / "tum", "--config", dir / "cam.ini", "--out", dir / "o", "--set",
                            "input.stride=2"}),
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
    apps::SemanticMapperApp app;
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

// The annotated rawlog holds one CObservationSemanticRGBD per mapped keyframe, at the pose it was
// inserted at: replayed into an empty map it rebuilds the map semantic-mapper wrote.
TEST(SemanticMapperApp, AnnotatedRawlogReplaysIntoTheSameMap)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    std::ostringstream out;
    apps::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    // No thinning, no re-anchoring and no pruning at the end, so that the map is exactly the
    // inserted observations.
    ASSERT_EQ(
        app.run(fast({"--out", dir / "o", "--set", "input.max_frames=60", "--set",
                      "map.contribution_voxel=0", "--set", "map.reanchor_translation=100", "--set",
                      "map.reanchor_rotation_deg=180", "--set", "map.prune_near_movers=0"}),
                out),
        0);
    maps::CSemanticPointsMap replay;
    mrpt::io::CFileGZInputStream in(dir / "o/annotated.rawlog");
    auto arch = mrpt::serialization::archiveFrom(in);
    size_t n = 0;
    for (;;)
    {
        mrpt::serialization::CSerializable::Ptr obj;
        try
        {
            arch >> obj;
        }
        catch (const std::exception&)
        {
            break;  // end of file
        }
        auto obs = std::dynamic_pointer_cast<maps::CObservationSemanticRGBD>(obj);
        ASSERT_TRUE(obs) << "entry " << n;
        EXPECT_EQ(obs->labels.size(), obs->colour.size());
        EXPECT_EQ(obs->dynamicMask.size(), obs->colour.size());
        EXPECT_EQ(cv::countNonZero(obs->labels != 255), 0) << "backend none: every pixel void";
        replay.insertObservation(*obs);
        n++;
    }
    EXPECT_EQ(n, app.result().keyframes);
    maps::CSemanticPointsMap written;
    written.loadPly(dir / "o/semantic_points.ply");
    ASSERT_GT(written.size(), 1000u);
    // The same pixels through the same poses; only float rounding at voxel borders differs.
    EXPECT_NEAR(static_cast<double>(replay.size()), static_cast<double>(written.size()),
                0.01 * static_cast<double>(written.size()));
}

// Every key the Parameters structs read is documented in config/default.ini, and every key there
// is one they read (the reference docs/configuration.md points to).
TEST(SemanticMapperApp, DefaultIniDocumentsEveryConfigurationKey)
{
    auto keys = [](const std::string& text)
    {
        std::set<std::string> out;
        std::istringstream in(text);
        std::string section;
        for (std::string line; std::getline(in, line);)
        {
            if (line.empty() || line[0] == '#')
                continue;
            if (line[0] == '[')
            {
                section = line.substr(1, line.find(']') - 1);
                continue;
            }
            const auto eq = line.find('=');
            if (eq == std::string::npos)
                continue;
            std::string key = line.substr(0, eq);
            key.erase(key.find_last_not_of(" \t") + 1);
            std::string full = section;
            full += ".";
            full += key;
            out.insert(full);
        }
        return out;
    };
    const auto reference = keys(apps::SemanticMapperApp::configurationReference());
    const auto documented =
        keys(test::readTextFile(std::string(SMAP_SOURCE_DIR) + "/config/default.ini"));
    EXPECT_GT(reference.size(), 100u);
    for (const auto& k : reference)
        EXPECT_EQ(documented.count(k), 1u) << k << " is missing from config/default.ini";
    for (const auto& k : documented)
        EXPECT_EQ(reference.count(k), 1u) << k << " in config/default.ini is read by no component";
    // And the file loads as it is.
    test::TempDir dir;
    std::ostringstream out;
    apps::SemanticMapperApp app;
    EXPECT_EQ(app.run({"--print-config"}, out), 0);
    EXPECT_NE(out.str().find("[pipeline]"), std::string::npos);
}
