// Tracking speed on a real 640x480 sequence (default ../shared/data/7scenes-redkitchen): runs
// the whole sequence through RgbdSlam (tracking in this thread, local mapping in its own, as
// the app does) several times and prints the median per-frame tracking time with its
// breakdown (extraction, matching, optimisation), and frames/s of the whole run (reading and
// decoding included). A timing program, not a test: see docs/benchmarks.md.
//
// Usage: bench_tracking [TUM_DIR] [--config FILE] [--runs N] [--max-frames N] [--sync]
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "BenchStats.h"
#include "smap/apps/AppMain.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/FrameSource.h"
#include "smap/slam/RgbdSlam.h"

using namespace smap;
using smap::bench::median;
using smap::bench::quantile;

namespace
{
const char* const kUsage =
    "Usage: bench_tracking [TUM_DIR|RAWLOG] [--config FILE] [--runs N] [--max-frames N] [--sync]\n"
    "\n"
    "Times tracking (ORB extraction, matching, pose optimisation; local mapping in its own\n"
    "thread unless --sync) over a whole recording, --runs times (default 3), and prints the\n"
    "median per-frame times and frames/s. Defaults: ../shared/data/7scenes-redkitchen with\n"
    "config/7scenes.ini. Exit codes: 0 ok, 1 internal error, 2 bad input.\n";

int run(const std::vector<std::string>& args)
{
    apps::CommandLine cl;  // strict: an unknown option is an error, not an input path
    cl.option("config").option("runs").option("max-frames").flag("sync").flag("help");
    cl.parse(args);
    if (cl.has("help"))
    {
        std::cout << kUsage;
        return apps::kExitOk;
    }
    if (cl.positionals().size() > 1)
        throw core::InputError("bench_tracking takes at most one input (see --help)");
    const std::string input = cl.positionals().empty()
                                  ? std::string(SMAP_SHARED_DIR) + "/data/7scenes-redkitchen"
                                  : cl.positionals()[0];
    const std::string config =
        cl.value("config").value_or(std::string(SMAP_SOURCE_DIR) + "/config/7scenes.ini");
    const int runs = static_cast<int>(cl.integer("runs", 3));
    const long maxFrames = cl.integer("max-frames", 0);
    const bool sync = cl.has("sync");
    if (runs < 1 || maxFrames < 0)
        throw core::InputError("--runs must be >= 1 and --max-frames >= 0");
    core::TrackedConfig cfg;
    cfg.loadFile(config);
    io::FrameSourceParameters sp;
    features::OrbParameters orb;
    slam::TrackerParameters tp;
    slam::LocalMappingParameters mp;
    cfg.load(sp);
    cfg.load(orb);
    cfg.load(tp);
    cfg.load(mp);
    sp.max_frames = static_cast<size_t>(maxFrames);
    mp.threaded = !sync;

    std::vector<double> runFps, runTrack, runExtract, runMatch, runOpt, runTotal;
    for (int r = 0; r < runs; ++r)
    {
        auto source = io::openFrameSource(input, sp);
        source->setMinLoggingLevel(mrpt::system::LVL_ERROR);
        slam::RgbdSlam slam(orb, tp, mp);
        slam.setLoggingLevel(mrpt::system::LVL_ERROR);
        std::vector<double> ext, match, opt, track, total;
        size_t n = 0, withPose = 0;
        const auto t0 = std::chrono::steady_clock::now();
        while (auto f = source->next())
        {
            const auto res = slam.process(*f);
            ext.push_back(res.timings.extraction_ms);
            match.push_back(res.timings.matching_ms);
            opt.push_back(res.timings.optimisation_ms);
            track.push_back(res.timings.total_ms);
            total.push_back(res.timings.extraction_ms + res.timings.total_ms);
            withPose += slam::hasPose(res.status) ? 1 : 0;
            n++;
        }
        slam.finish();
        const double secs =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf(
            "run %d: %zu frames (%zu with pose) in %.2f s = %.1f frames/s | per frame median: "
            "extraction %.2f ms, matching %.2f ms, optimisation %.2f ms, tracking %.2f ms, "
            "extraction+tracking %.2f ms (95%%: %.2f ms, max %.2f ms)\n",
            r + 1, n, withPose, secs, n / secs, median(ext), median(match), median(opt),
            median(track), median(total), quantile(total, 0.95), quantile(total, 1.0));
        runFps.push_back(n / secs);
        runExtract.push_back(median(ext));
        runMatch.push_back(median(match));
        runOpt.push_back(median(opt));
        runTrack.push_back(median(track));
        runTotal.push_back(median(total));
    }
    std::printf(
        "median of %d runs: %.1f frames/s whole run; per frame extraction %.2f ms, matching "
        "%.2f ms, optimisation %.2f ms, tracking (matching + optimisation + bookkeeping) %.2f "
        "ms, extraction + tracking %.2f ms\n",
        runs, median(runFps), median(runExtract), median(runMatch), median(runOpt),
        median(runTrack), median(runTotal));
    return apps::kExitOk;
}
}  // namespace

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("bench_tracking", std::cerr,
                                  [&] {
                                      return run({argv + 1, argv + argc});
                                  });
}
