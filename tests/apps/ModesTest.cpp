// The shipped modes: config/modes/paper.ini is the paper's method, with every addition beyond it
// off; --reproducible gives byte-identical outputs.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "TestData.h"
#include "smap/apps/SemanticMapperApp.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
/// Every configuration key of `app` as it will run, as text.
mrpt::config::CConfigFileMemory effective(const apps::SemanticMapperApp& app)
{
    mrpt::config::CConfigFileMemory cfg;
    for (const auto* part : app.parameters.parts())
        part->saveToConfigFile(cfg, "");
    return cfg;
}

/// The parameters semantic-mapper runs with for these arguments (no run).
mrpt::config::CConfigFileMemory parametersFor(const std::vector<std::string>& args)
{
    apps::SemanticMapperApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    std::ostringstream out;
    EXPECT_TRUE(app.initialize(args, out)) << out.str();
    return effective(app);
}

/// An addition beyond the paper: its key, and the value that turns it off.
struct Addition
{
    const char* section;
    const char* key;
    double off;
};

/// Each addition beyond the paper that is on by default (docs/method.md, "Beyond the paper").
const std::vector<Addition> kAdditions = {
    {"tracking", "keyframe_min_interval_s", 0},
    {"tracking", "depth_edge_ratio", 0},
    {"tracking", "revisit_radius", 0},
    {"tracking", "carried_search_s", 0},
    {"tracking", "relocalisation_sweep", 0},
    {"tracking", "reanchor_after_s", 0},
    {"tracking", "fallback_weight", 0},
    {"local_mapping", "ba_min_shared_observations", 0},
    {"local_mapping", "global_ba_iterations", 0},
    {"loop_closing", "enabled", 0},
    {"semantic_evidence", "enabled", 0},
    {"segmentation", "zoom_crops", 0},
    {"association", "grow_pixels", 0},
    {"association", "movable_prior", 2},  // above 1: no class is dynamic by its prior alone
    {"map", "prune_near_movers", 0},
    {"map", "confirm_near_movers", 0},
    {"map", "see_through_margin", 0},
    {"map", "see_through_majority", 0},
    {"map", "movable_body_radius", 0},
};

double number(const mrpt::config::CConfigFileMemory& cfg, const Addition& a)
{
    const std::string v = cfg.read_string(a.section, a.key, "", true);
    if (v == "true")
        return 1.0;
    if (v == "false")
        return 0.0;
    return std::stod(v);
}

std::string paperIni()
{
    return std::string(SMAP_SOURCE_DIR) + "/config/modes/paper.ini";
}

std::vector<uint8_t> readBytes(const fs::path& path)
{
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// The files under `dir`, relative to it, sorted.
std::vector<std::string> filesUnder(const fs::path& dir)
{
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file())
            out.push_back(fs::relative(e.path(), dir).string());
    std::sort(out.begin(), out.end());
    return out;
}
}  // namespace

TEST(SemanticMapperApp, PaperModeTurnsOffEveryAdditionBeyondThePaper)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    const auto defaults = parametersFor({});
    const auto paper = parametersFor({"--config", paperIni()});
    for (const Addition& a : kAdditions)
    {
        const std::string name = std::string("[") + a.section + "] " + a.key;
        EXPECT_NE(number(defaults, a), a.off) << name << " is not on by default: not an addition";
        EXPECT_EQ(number(paper, a), a.off) << name << " is not turned off by paper.ini";
    }
    // The paper's own choices: its flow filter and Algorithm 1's parameters.
    EXPECT_EQ(paper.read_string("dynamic", "mode", ""), "paper");
    EXPECT_EQ(paper.read_double("dynamic", "tau", 0), 7.0);
    EXPECT_EQ(paper.read_int("association", "num_points", 0), 20);
    EXPECT_EQ(paper.read_double("association", "depth_tolerance", 0), 0.1);
    EXPECT_EQ(paper.read_double("association", "pixel_radius", 0), 5.0);
    EXPECT_EQ(paper.read_double("crf", "appearance_xy", 0), 80.0);
}

TEST(SemanticMapperApp, ReproducibleSwitchSetsTheDeterministicKeys)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    const auto defaults = parametersFor({});
    EXPECT_TRUE(defaults.read_bool("loop_closing", "threaded", false));
    EXPECT_EQ(defaults.read_double("semantic_evidence", "mask_latency_s", -1), 0.0);
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"--reproducible"}, {"--set", "pipeline.reproducible=true"}})
    {
        const auto r = parametersFor(args);
        EXPECT_TRUE(r.read_bool("pipeline", "reproducible", false)) << args[0];
        EXPECT_FALSE(r.read_bool("loop_closing", "threaded", true)) << args[0];
        EXPECT_FALSE(r.read_bool("local_mapping", "threaded", true)) << args[0];
        EXPECT_GT(r.read_double("semantic_evidence", "mask_latency_s", 0), 0.0) << args[0];
        EXPECT_EQ(r.read_string("pipeline", "when_full", ""), "wait") << args[0];
    }
    // A latency of its own is kept.
    const auto own =
        parametersFor({"--reproducible", "--set", "semantic_evidence.mask_latency_s=0.2"});
    EXPECT_EQ(own.read_double("semantic_evidence", "mask_latency_s", 0), 0.2);
}

// Two reproducible runs of the main job on the sample (segmentation, loop closing, snapshots and
// every output on) write the same bytes in every file.
TEST(SemanticMapperApp, ReproducibleRunsWriteIdenticalFiles)
{
    SMAP_REQUIRE_DATA(apps::SemanticMapperApp::defaultInput());
    test::TempDir dir;
    for (const std::string run : {"a", "b"})
    {
        apps::SemanticMapperApp app;
        app.setMinLoggingLevel(mrpt::system::LVL_WARN);
        std::ostringstream out;
        ASSERT_EQ(
            app.run({"--out", dir / run, "--reproducible", "--set", "input.max_frames=60"}, out),
            0);
    }
    const auto files = filesUnder(dir / "a");
    EXPECT_EQ(files, filesUnder(dir / "b"));
    EXPECT_GE(files.size(), 12u);
    for (const auto& f : files)
    {
        const auto a = readBytes(fs::path(dir / "a") / f);
        EXPECT_FALSE(a.empty()) << f;
        EXPECT_TRUE(a == readBytes(fs::path(dir / "b") / f)) << f << " differs between two runs";
    }
    const std::string metrics = test::readTextFile(dir / "a/metrics.json");
    EXPECT_EQ(metrics.find("\"timings\""), std::string::npos) << "timings measure the machine";
    EXPECT_NE(metrics.find("\"frames_with_pose\""), std::string::npos);
}
