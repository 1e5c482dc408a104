// Rendering speed of the synthetic generator (640x480: colour, depth, labels, instances,
// dynamic mask, Kinect noise) and the ORB keypoint count the scene offers per frame.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "smap/sim/SequenceGenerator.h"

namespace
{
void BM_RenderFrame(benchmark::State& state, const char* preset)
{
    smap::sim::GeneratorOptions o;
    o.preset = preset;
    smap::sim::SequenceGenerator gen(o);
    size_t i = 0;
    for (auto _ : state)
    {
        auto f = gen.frame(i++ % 300);
        benchmark::DoNotOptimize(f.rendered.depth.data);
    }
    state.SetItemsProcessed(state.iterations());
}

/// Median number of ORB keypoints (1000 requested, 8 levels, scale 1.2) over 100 frames.
void BM_OrbKeypointsPerFrame(benchmark::State& state, const char* preset)
{
    smap::sim::GeneratorOptions o;
    o.preset = preset;
    smap::sim::SequenceGenerator gen(o);
    auto orb = cv::ORB::create(1000, 1.2f, 8);
    std::vector<double> counts;
    for (auto _ : state)
    {
        counts.clear();
        for (size_t i = 0; i < 300; i += 3)
        {
            const auto f = gen.frame(i);
            cv::Mat grey;
            cv::cvtColor(f.rendered.colour, grey, cv::COLOR_BGR2GRAY);
            std::vector<cv::KeyPoint> kp;
            orb->detect(grey, kp);
            counts.push_back(static_cast<double>(kp.size()));
        }
    }
    std::nth_element(counts.begin(),
                     counts.begin() + static_cast<std::ptrdiff_t>(counts.size() / 2), counts.end());
    state.counters["median_keypoints"] = counts[counts.size() / 2];
    state.counters["min_keypoints"] = *std::min_element(counts.begin(), counts.end());
}
}  // namespace

BENCHMARK_CAPTURE(BM_RenderFrame, walking_xyz, "walking_xyz")
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, static_halfsphere, "static_halfsphere")
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_OrbKeypointsPerFrame, walking_xyz, "walking_xyz")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_OrbKeypointsPerFrame, static_handheld, "static_handheld")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_MAIN();
