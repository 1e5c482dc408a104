// Cost of the dynamic feature filter per 640x480 frame: the time DynamicFilter::process adds
// before tracking (ego-motion, image pyramid or warp, Lucas-Kanade, decision), per mode.
// Frames and their ORB features are prepared first, so only the filter is timed; one thread.
// Default input: the synthetic walking_xyz preset rendered in memory (150 frames); or a TUM
// folder. Prints per-run medians and the median over runs. A timing program, not a test:
// see docs/benchmarks.md.
//
// Usage: bench_dynamic [TUM_DIR --config FILE] [--frames N] [--runs N] [--set dynamic.K=V]...
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "BenchStats.h"
#include "smap/apps/AppMain.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/io/FrameSource.h"
#include "smap/sim/SequenceGenerator.h"
#include "smap/slam/RgbdSlam.h"

using namespace smap;
using smap::bench::median;

namespace
{
struct Prepared
{
    core::RgbdFrame frame;
    features::FeatureSet features;
};
}  // namespace

const char* const kUsage =
    "Usage: bench_dynamic [TUM_DIR --config FILE] [--frames N] [--runs N] [--set "
    "dynamic.K=V]...\n"
    "\n"
    "Times the dynamic feature filter per frame, per mode (off, paper, strong), on the\n"
    "synthetic walking_xyz preset rendered in memory (default, 150 frames) or a TUM folder;\n"
    "prints per-run medians and the median over --runs (default 5). Exit codes: 0 ok,\n"
    "1 internal error, 2 bad input.\n";

int run(int argc, char** argv)
{
    apps::CommandLine cl;  // strict: an unknown option is an error, not an input path
    cl.option("config").option("runs").option("frames").option("set").flag("help");
    cl.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cl.has("help"))
    {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (cl.positionals().size() > 1)
        throw core::InputError("bench_dynamic takes at most one TUM folder");
    std::string input = cl.positionals().empty() ? std::string() : cl.positionals()[0];
    const std::string config = cl.value("config").value_or("");
    const int runs = static_cast<int>(cl.integer("runs", 5));
    const auto frames = static_cast<size_t>(cl.integer("frames", 150));
    const std::vector<std::string> sets = cl.values("set");
    core::TrackedConfig cfg;
    if (!config.empty())
        cfg.loadFile(config);
    for (const auto& s : sets)
        cfg.applyOverride(s);
    features::OrbParameters orb;
    slam::TrackerParameters tp;
    slam::LocalMappingParameters mp;
    dynamic::DynamicParameters dp;
    io::FrameSourceParameters sp;
    cfg.load(orb);
    cfg.load(tp);
    cfg.load(mp);
    cfg.load(dp);
    cfg.load(sp);
    const slam::RgbdSlam slam(orb, tp, mp);

    std::vector<Prepared> seq;
    if (input.empty())
    {
        sim::GeneratorOptions o;
        o.preset = "walking_xyz";
        sim::SequenceGenerator gen(o);
        for (size_t i = 0; i < frames; ++i)
        {
            const core::RgbdFrame r = gen.rgbdFrame(i);
            seq.push_back({r, slam.prepare(r).features});
        }
        input = "synthetic walking_xyz (in memory)";
    }
    else
    {
        sp.max_frames = frames;
        auto source = io::openFrameSource(input, sp);
        source->setMinLoggingLevel(mrpt::system::LVL_ERROR);
        while (auto f = source->next())
            seq.push_back({*f, slam.prepare(*f).features});
    }
    std::printf("%zu frames of %s, %dx%d, %d runs\n", seq.size(), input.c_str(),
                seq.front().frame.colour.cols, seq.front().frame.colour.rows, runs);

    for (const auto mode :
         {dynamic::FilterMode::Off, dynamic::FilterMode::Paper, dynamic::FilterMode::Strong})
    {
        dp.mode = mode;
        std::vector<double> total, ego, warp, flow, other, dyn;
        for (int r = 0; r < runs; ++r)
        {
            dynamic::DynamicFilter filter(dp);
            std::vector<double> t, e, w, f, o, d;
            for (const auto& p : seq)
            {
                const auto t0 = std::chrono::steady_clock::now();
                const auto res = filter.process(p.frame.colour, p.frame.depth, p.features,
                                                p.frame.camera, p.frame.timestamp);
                const double ms =
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                        .count();
                if (!res.evaluated)
                    continue;
                t.push_back(ms);
                e.push_back(res.ego_motion_ms);
                w.push_back(res.warp_ms);
                f.push_back(res.flow_ms);
                o.push_back(ms - res.ego_motion_ms - res.warp_ms - res.flow_ms);
                d.push_back(static_cast<double>(res.numDynamic()));
            }
            std::printf(
                "  %-6s run %d: per frame median %.2f ms (ego-motion %.2f, %s %.2f, "
                "flow %.2f, rest %.2f), %.0f dynamic keypoints\n",
                dynamic::toString(mode).c_str(), r + 1, median(t), median(e),
                mode == dynamic::FilterMode::Strong ? "pyramid" : "warp", median(w), median(f),
                median(o), median(d));
            total.push_back(median(t));
            ego.push_back(median(e));
            warp.push_back(median(w));
            flow.push_back(median(f));
            other.push_back(median(o));
        }
        std::printf(
            "%-6s median of %d runs: %.2f ms per frame (ego-motion %.2f, %s %.2f, flow "
            "%.2f, rest %.2f)\n",
            dynamic::toString(mode).c_str(), runs, median(total), median(ego),
            mode == dynamic::FilterMode::Strong ? "pyramid" : "warp", median(warp), median(flow),
            median(other));
    }
    return 0;
}

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("bench_dynamic", std::cerr, [&] { return run(argc, argv); });
}
