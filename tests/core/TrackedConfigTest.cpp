#include <gtest/gtest.h>

#include <fstream>

#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"

using smap::core::InputError;
using smap::core::TrackedConfig;

TEST(TrackedConfig, ReportsUnknownKeysWithFileAndValidKeys)
{
    TrackedConfig cfg;
    cfg.loadText("[tum]\ndepth_factor = 1000\ndepth_factr = 5\n[nosuch]\nx = 1\n", "my.ini");
    EXPECT_DOUBLE_EQ(cfg.read_double("tum", "depth_factor", 5000.0), 1000.0);
    cfg.read_double("tum", "max_dt", 0.02);
    const auto unused = cfg.unusedKeys();
    ASSERT_EQ(unused.size(), 2u);
    try
    {
        cfg.ensureAllKeysUsed();
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("my.ini"), std::string::npos) << msg;
        EXPECT_NE(msg.find("depth_factr"), std::string::npos) << msg;
        EXPECT_NE(msg.find("depth_factor, max_dt"), std::string::npos) << msg;
        EXPECT_NE(msg.find("[nosuch] x"), std::string::npos) << msg;
        EXPECT_NE(msg.find("unknown section"), std::string::npos) << msg;
    }
}

TEST(TrackedConfig, AllKeysReadPasses)
{
    TrackedConfig cfg;
    cfg.loadText("[a]\nK = 2\n", "t.ini");
    EXPECT_EQ(cfg.read_int("a", "k", 0), 2);  // keys are case-insensitive, as in MRPT
    EXPECT_NO_THROW(cfg.ensureAllKeysUsed());
}

TEST(TrackedConfig, OverridesReplaceFileValues)
{
    TrackedConfig cfg;
    cfg.loadText("[input]\nmax_frames = 5\n", "t.ini");
    cfg.applyOverride("input.max_frames=7");
    cfg.applyOverride(" tum.depth_factor = 1000 ");
    EXPECT_EQ(cfg.read_int("input", "max_frames", 0), 7);
    EXPECT_DOUBLE_EQ(cfg.read_double("tum", "depth_factor", 0), 1000.0);
}

TEST(TrackedConfig, MalformedOverrideIsAnError)
{
    TrackedConfig cfg;
    for (const char* bad : {"input", "input=3", ".k=1", "input.=1", "inputmax_frames=1"})
        EXPECT_THROW(cfg.applyOverride(bad), InputError) << bad;
}

TEST(TrackedConfig, LoadsYamlAndReportsMissingFile)
{
    smap::test::TempDir dir;
    const std::string path = dir / "c.yaml";
    {
        std::ofstream f(path);
        f << "tum:\n  depth_factor: 1000\n";
    }
    TrackedConfig cfg;
    cfg.loadFile(path);
    EXPECT_DOUBLE_EQ(cfg.read_double("tum", "depth_factor", 0), 1000.0);

    TrackedConfig missing;
    try
    {
        missing.loadFile(dir / "nope.ini");
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("nope.ini"), std::string::npos);
    }
}

TEST(TrackedConfig, YamlSubsetWithUnscopedKeysCommentsAndQuotes)
{
    TrackedConfig cfg;
    cfg.loadYamlText(
        "# c\ntop: 1\ncamera:\n  fx: 525.0   # focal\n  name: \"kinect #2\"\ntum:\n  "
        "use_associations: false\n",
        "c.yaml");
    EXPECT_EQ(cfg.read_int("", "top", 0), 1);
    EXPECT_DOUBLE_EQ(cfg.read_double("camera", "fx", 0), 525.0);
    EXPECT_EQ(cfg.read_string("camera", "name", ""), "kinect #2");
    EXPECT_FALSE(cfg.read_bool("tum", "use_associations", true));
    EXPECT_NO_THROW(cfg.ensureAllKeysUsed());

    TrackedConfig bad;
    try
    {
        bad.loadYamlText("a:\n  b:\n    c: 1\n", "deep.yaml");
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("deep.yaml:2:"), std::string::npos) << e.what();
    }
    EXPECT_THROW(bad.loadYamlText("  x: 1\n", "y.yaml"), InputError);
    EXPECT_THROW(bad.loadYamlText("justtext\n", "y.yaml"), InputError);
}

TEST(TrackedConfig, ParserAndValueFailuresBecomeInputErrorsNamingTheSource)
{
    TrackedConfig cfg;
    // MRPT's INI parser rejects malformed $env{} expansions with its own exception type.
    bool threw = false;
    try
    {
        cfg.loadText("9camut$env{3\n[vum]\n", "env.ini");
    }
    catch (const InputError& e)
    {
        threw = true;
        EXPECT_NE(std::string(e.what()).find("env.ini"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(threw);

    struct Strict : mrpt::config::CLoadableOptions
    {
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string&) override
        {
            if (c.read_int("s", "n", 0) < 0)
                throw InputError("[s] n must be >= 0");
            if (c.read_int("s", "m", 0) > 0)
                throw std::runtime_error("library failure");
        }
    } strict;
    cfg.loadText("[s]\nn = -1\n", "neg.ini");
    try
    {
        cfg.load(strict);
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_EQ(std::string(e.what()), "config 'neg.ini': [s] n must be >= 0");
    }
    cfg.loadText("[s]\nm = 1\n", "m.ini");
    EXPECT_THROW(cfg.load(strict), InputError);
}

TEST(TrackedConfig, LaterFilesMergeOverEarlierOnes)
{
    smap::test::TempDir dir;
    std::ofstream(dir / "camera.ini") << "[tum]\ndepth_factor = 1000\nmax_dt = 0.03\n";
    std::ofstream(dir / "seg.ini") << "[tum]\nmax_dt = 0.05\n[crf]\niterations = 7\n";
    TrackedConfig cfg;
    cfg.loadFile(dir / "camera.ini");
    cfg.mergeFile(dir / "seg.ini");
    EXPECT_DOUBLE_EQ(cfg.read_double("tum", "depth_factor", 0.0), 1000.0);
    EXPECT_DOUBLE_EQ(cfg.read_double("tum", "max_dt", 0.0), 0.05);
    EXPECT_EQ(cfg.read_int("crf", "iterations", 0), 7);
    EXPECT_NE(cfg.sourceName().find("seg.ini"), std::string::npos);
    EXPECT_THROW(cfg.mergeFile(dir / "missing.ini"), InputError);
}

TEST(TrackedConfig, ErrorsAfterAnOverrideNameSetAmongTheSources)
{
    // A typo in --set must not be blamed on a file alone (e.g. a preset the user never named).
    TrackedConfig cfg;
    cfg.loadText("[tum]\ndepth_factor = 1000\n", "config/7scenes.ini");
    cfg.applyOverride("tum.bogus=1");
    cfg.applyOverride("tum.depth_factor=5000");
    EXPECT_EQ(cfg.sourceName(), "config/7scenes.ini + --set");
    try
    {
        cfg.ensureAllKeysUsed();
        ADD_FAILURE() << "unknown key accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("config 'config/7scenes.ini + --set'"),
                  std::string::npos)
            << e.what();
    }
}
