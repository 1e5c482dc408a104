// The installed commands as a user runs them: exit codes and messages.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "CliHelpers.h"
#include "TestData.h"

namespace
{
using smap::test::bin;
using smap::test::CmdResult;
using smap::test::jsonNumber;
using smap::test::run;

/// The IoU of the class `name` in a Table III block of metrics.json (NaN when absent).
double classIou(const std::string& json, const std::string& block, const std::string& name)
{
    const size_t at = json.find("\"" + block + "\":");
    if (at == std::string::npos)
        return std::nan("");
    const size_t cls = json.find("\"name\": \"" + name + "\"", at);
    return cls == std::string::npos ? std::nan("") : jsonNumber(json.substr(cls), {"iou"});
}
}  // namespace

// The README's main job, as shipped and as a user without ../shared runs it: the embedded
// sample through the default configuration, every keyframe segmented by the model that ships in
// models/ (found in the build tree's data folder). Trajectory accuracy, map contents and the
// segmentation scores against the sample's ground truth are checked with tolerances, as MRPT's
// own SLAM app tests do.
TEST(Cli, MainJobRunsOnTheEmbeddedDefault)
{
    smap::test::TempDir dir;
    const CmdResult r = run(bin("semantic-mapper") + " --out " + (dir / "out"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("outputs in"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("200 frames from"), std::string::npos) << r.output;
    const std::string shipped = (std::filesystem::path(smap::test::binDir()).parent_path() /
                                 "share/semantic-mapper/models/espnetv2-voc/"
                                 "espnetv2_s2.0_voc_320x240.onnx")
                                    .string();
    EXPECT_NE(r.output.find("loaded " + shipped), std::string::npos)
        << "the shipped model, from the data folder beside bin/\n"
        << r.output;
    const std::string m = smap::test::readTextFile(dir / "out/metrics.json");
    EXPECT_NE(m.find("onnx espnetv2_s2.0_voc_320x240.onnx"), std::string::npos) << m;
    // Trajectory: ATE of the 200 synthetic frames (measured 2.5 cm) and every frame tracked.
    EXPECT_LT(jsonNumber(m, {"evaluation", "ate", "rmse"}), 0.04) << m;
    EXPECT_GE(jsonNumber(m, {"tracking", "frames_with_pose"}), 195.0) << m;
    // Keyframes: all mapped, every one segmented and scored against the sample's labels.
    const double kf = jsonNumber(m, {"keyframes", "submitted"});
    EXPECT_GE(kf, 10.0);
    EXPECT_EQ(jsonNumber(m, {"keyframes", "mapped"}), kf);
    EXPECT_EQ(jsonNumber(m, {"segmentation_scores", "frames_scored"}), kf) << m;
    EXPECT_EQ(jsonNumber(m, {"segmentation_scores", "segmentation", "frames"}), kf) << m;
    // The people are real person imagery: the CNN + CRF finds them (measured IoU 0.82), and
    // Algorithm 1's dynamic mask covers them (measured 0.64).
    EXPECT_GE(classIou(m, "segmentation", "person"), 0.6) << m;
    EXPECT_GE(classIou(m, "dynamic_mask", "dynamic"), 0.6) << m;
    const double dyn = jsonNumber(m, {"keyframes", "dynamic_pixel_fraction"});
    EXPECT_GT(dyn, 0.02) << "two people walk through the view";
    EXPECT_LT(dyn, 0.50) << "they fill much of it, not most";
    // Maps: the office (about 5 x 4 m) at 2 cm voxels and 5 cm octomap voxels (measured 123k
    // points and 10k voxels).
    EXPECT_GT(jsonNumber(m, {"map", "points"}), 60000.0) << m;
    EXPECT_LT(jsonNumber(m, {"map", "points"}), 250000.0) << m;
    EXPECT_GT(jsonNumber(m, {"map", "octomap_occupied_voxels"}), 5000.0) << m;
    for (const char* f : {"snapshots/map_by_class.png", "snapshots/map_by_colour.png",
                          "snapshots/trajectory.png", "snapshots/ate.png", "semantic_points.ply",
                          "semantic_octomap.ot", "annotated.rawlog", "semantic_map.bin"})
        EXPECT_TRUE(std::ifstream(dir / (std::string("out/") + f)).good()) << f;
}

// Ctrl-C: the run stops reading, finishes the queued keyframes and writes complete outputs for
// the frames it processed, and exits with 130.
TEST(Cli, InterruptedRunLeavesCompleteOutputs)
{
    smap::test::TempDir dir;
    // Started in the background; SIGINT once it has written its effective configuration (it
    // is then processing frames), as a user's Ctrl-C would arrive.
    const std::string out = dir / "out";
    const CmdResult r = run("bash -c '" + bin("semantic-mapper") + " --out " + out +
                            " --set segmentation.backend=none --set output.snapshots=false & "
                            "pid=$!; for i in $(seq 100); do [ -f " +
                            out +
                            "/config-effective.ini ] && break; sleep 0.1; done; "
                            "sleep 0.3; kill -INT $pid; wait $pid; echo exit=$?'");
    EXPECT_NE(r.output.find("exit=130"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("interrupted"), std::string::npos) << r.output;
    const std::string m = smap::test::readTextFile(dir / "out/metrics.json");
    EXPECT_NE(m.find("\"interrupted\": true"), std::string::npos) << m;
    const double frames = jsonNumber(m, {"frames"});
    EXPECT_GT(frames, 0.0);
    EXPECT_LT(frames, 200.0);
    // The trajectory has a line for every tracked frame (2 comment lines).
    const std::string traj = smap::test::readTextFile(dir / "out/trajectory.txt");
    EXPECT_EQ(static_cast<double>(std::count(traj.begin(), traj.end(), '\n')) - 2.0,
              jsonNumber(m, {"tracking", "frames_with_pose"}));
    for (const char* f : {"semantic_points.ply", "semantic_octomap.ot", "annotated.rawlog",
                          "frames.csv", "keyframes.txt"})
        EXPECT_TRUE(std::ifstream(dir / (std::string("out/") + f)).good()) << f;
}

TEST(Cli, BadInputExitsWithCodeTwoAndNamesTheProblem)
{
    smap::test::TempDir dir;
    CmdResult r = run(bin("semantic-mapper") + " " + (dir / "no-such-input"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("no-such-input"), std::string::npos) << r.output;

    std::ofstream(dir / "gt.txt") << "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n";
    r = run(bin("smap-eval") + " ate " + (dir / "gt.txt") + " " + (dir / "gt.txt"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("gt.txt:2:"), std::string::npos) << r.output;

    r = run(bin("tum2rawlog") + " --bogus");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("unknown option '--bogus'"), std::string::npos) << r.output;

    r = run(bin("smap-eval") + " --help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("smap-eval ate GT EST"), std::string::npos);
}

// Every command and every benchmark program prints its usage on --help and exits with 0 (the
// Google Benchmark ones print the library's usage); none ends in std::terminate.
TEST(Cli, EveryProgramPrintsItsUsageOnHelp)
{
    std::vector<std::string> programs = {"semantic-mapper", "tum2rawlog", "smap-eval",
                                         "smap-segment", "smap-synth"};
    // Benchmarks are built only where Google Benchmark is installed.
    for (const char* b : {"bench_tracking", "bench_dynamic", "eval_maps", "bench_io", "bench_sim",
                          "bench_features", "bench_segmentation"})
        if (std::filesystem::exists(bin(b)))
            programs.emplace_back(b);
    for (const auto& name : programs)
    {
        const CmdResult r = run(bin(name) + " --help");
        EXPECT_EQ(r.code, 0) << name << "\n" << r.output;
        const bool usage = r.output.find("Usage") != std::string::npos ||
                           r.output.find("--benchmark_filter") != std::string::npos;
        EXPECT_TRUE(usage) << name << "\n" << r.output;
        EXPECT_EQ(r.output.find("terminate"), std::string::npos) << name;
    }
    // A wrong option is bad input, said in one line, not an abort.
    if (std::filesystem::exists(bin("bench_tracking")))
    {
        const CmdResult bad = run(bin("bench_tracking") + " --no-such-option");
        EXPECT_EQ(bad.code, 2) << bad.output;
        EXPECT_NE(bad.output.find("unknown option '--no-such-option'"), std::string::npos);
    }
}
