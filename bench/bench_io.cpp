// Reading + decoding speed of the 7-Scenes kitchen (1000 real 640x480 frames) as a TUM folder
// and as a rawlog made by tum2rawlog. items_per_second = frames/s (one frame per iteration).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <memory>

#include "smap/core/TrackedConfig.h"
#include "smap/io/FrameSource.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumToRawlogConverter.h"

namespace fs = std::filesystem;

namespace
{
const std::string kFolder = std::string(SMAP_SHARED_DIR) + "/data/7scenes-redkitchen";

smap::io::FrameSourceParameters sevenScenesParameters()
{
    smap::core::TrackedConfig cfg;
    cfg.loadFile(std::string(SMAP_SOURCE_DIR) + "/config/7scenes.ini");
    smap::io::FrameSourceParameters p;
    cfg.load(p);
    return p;
}

/// The converted rawlog, made once per process in the temp dir and removed at exit.
struct ConvertedRawlog
{
    fs::path dir = fs::temp_directory_path() / ("smap-bench-" + std::to_string(::getpid()));
    std::string path;
    ConvertedRawlog()
    {
        fs::create_directories(dir);
        const auto p = sevenScenesParameters();
        smap::io::TumSource src(kFolder, p);
        smap::io::TumToRawlogConverter conv;
        conv.setMinLoggingLevel(mrpt::system::LVL_WARN);
        path = conv.convert(src, p.tum_depth_factor, (dir / "kitchen.rawlog").string()).rawlogPath;
    }
    ~ConvertedRawlog()
    {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

const std::string& convertedRawlog()
{
    static const ConvertedRawlog converted;
    return converted.path;
}

void readFrames(benchmark::State& state, const std::string& input)
{
    const auto params = sevenScenesParameters();
    auto src = smap::io::openFrameSource(input, params);
    src->setMinLoggingLevel(mrpt::system::LVL_WARN);
    for (auto _ : state)
    {
        auto f = src->next();
        if (!f)
        {
            state.PauseTiming();
            src = smap::io::openFrameSource(input, params);
            src->setMinLoggingLevel(mrpt::system::LVL_WARN);
            state.ResumeTiming();
            f = src->next();
        }
        benchmark::DoNotOptimize(f->depth.data);
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_ReadTumFolder(benchmark::State& state)
{
    if (!fs::exists(kFolder))
    {
        state.SkipWithError(("7-Scenes not found at " + kFolder).c_str());
        return;
    }
    readFrames(state, kFolder);
}

void BM_ReadRawlog(benchmark::State& state)
{
    if (!fs::exists(kFolder))
    {
        state.SkipWithError(("7-Scenes not found at " + kFolder).c_str());
        return;
    }
    readFrames(state, convertedRawlog());
}
}  // namespace

BENCHMARK(BM_ReadTumFolder)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_ReadRawlog)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK_MAIN();
