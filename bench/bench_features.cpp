// ORB extraction alone (OrbExtractor::extract: pyramid, gridded FAST, orientation, descriptors)
// on 20 real 640x480 frames of the 7-Scenes kitchen, default [orb] parameters; one frame per
// iteration, items_per_second = frames/s. The extraction part of bench_tracking's breakdown,
// without the local-mapping thread beside it.
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "smap/features/OrbExtractor.h"

namespace
{
std::vector<cv::Mat> kitchenFrames()
{
    std::vector<cv::Mat> frames;
    for (int i = 0; i < 1000; i += 50)
    {
        char name[64];
        std::snprintf(name, sizeof(name), "/rgb/frame-%06d.jpg", i);
        cv::Mat grey = cv::imread(std::string(SMAP_SHARED_DIR) + "/data/7scenes-redkitchen" + name,
                                  cv::IMREAD_GRAYSCALE);
        if (!grey.empty())
            frames.push_back(grey);
    }
    return frames;
}

void orbExtraction(benchmark::State& state)
{
    static const std::vector<cv::Mat> frames = kitchenFrames();
    if (frames.empty())
    {
        state.SkipWithError("../shared/data/7scenes-redkitchen/rgb not found");
        return;
    }
    const smap::features::OrbExtractor extractor{smap::features::OrbParameters{}};
    size_t i = 0, keypoints = 0;
    for (auto _ : state)
    {
        const auto fs = extractor.extract(frames[i++ % frames.size()]);
        keypoints += fs.keypoints.size();
        benchmark::DoNotOptimize(fs.descriptors.data);
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["keypoints"] =
        benchmark::Counter(static_cast<double>(keypoints), benchmark::Counter::kAvgIterations);
}
BENCHMARK(orbExtraction)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
