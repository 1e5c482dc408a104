// Reading + decoding speed of the 7-Scenes kitchen (1000 real 640x480 frames) as a TUM folder
// and as a rawlog made by tum2rawlog (both with config/7scenes.ini, so depth is registered to
// the colour camera on the way); items_per_second = frames/s (one frame per iteration).
// BM_RegisterDepth: the registration alone, one 640x480 depth image (a real 7-Scenes one when
// ../shared is there) in the 7-Scenes geometry (585 px depth camera, 525.5 px colour camera
// 2.5 cm apart), on one core.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "smap/core/TrackedConfig.h"
#include "smap/io/DepthRegistration.h"
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

smap::core::PinholeCamera kinectCamera(double f)
{
    smap::core::PinholeCamera c;
    c.width = 640;
    c.height = 480;
    c.fx = c.fy = f;
    c.cx = 320;
    c.cy = 240;
    return c;
}

/// A real 7-Scenes depth image (frame 500) when ../shared is there, else a rendered-like room:
/// a wall at 3.5 m, a floor, a desk at 1.2 m and a box at 0.8 m, holes along their edges.
cv::Mat registrationInput()
{
    const std::string real = kFolder + "/depth/frame-000500.png";
    if (fs::exists(real))
    {
        const cv::Mat raw = cv::imread(real, cv::IMREAD_UNCHANGED);
        cv::Mat metres;
        raw.convertTo(metres, CV_32F, 1.0 / 1000.0);
        return metres;
    }
    cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(3.5F));
    for (int v = 300; v < 480; v++)  // floor: 1.5 m below the camera
        depth.row(v).setTo(std::min(3.5F, 1.5F * 525.0F / static_cast<float>(v - 240)));
    depth(cv::Rect(100, 220, 300, 120)).setTo(1.2F);
    depth(cv::Rect(420, 150, 120, 120)).setTo(0.8F);
    depth.col(100).setTo(0.0F);
    depth.col(400).setTo(0.0F);
    return depth;
}

void BM_RegisterDepth(benchmark::State& state)
{
    cv::setNumThreads(1);
    Eigen::Isometry3d T_colour_depth = Eigen::Isometry3d::Identity();
    T_colour_depth.translation() = Eigen::Vector3d(-0.025, 0, 0);
    const smap::io::DepthRegistration registration(kinectCamera(585.0), kinectCamera(525.5),
                                                   T_colour_depth);
    const cv::Mat depth = registrationInput();
    for (auto _ : state)
        benchmark::DoNotOptimize(registration.registerDepth(depth).data);
    state.SetItemsProcessed(state.iterations());
}
}  // namespace

BENCHMARK(BM_RegisterDepth)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_ReadTumFolder)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_ReadRawlog)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK_MAIN();
