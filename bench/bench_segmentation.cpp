// Segmentation cost on real 7-Scenes frames (Google Benchmark): the ESPNetv2 network alone at
// 320x240 (with and without its softmax), the upsampling of 21 probability planes to 640x480, the
// dense CRF alone (320x240, 21 labels, 5 iterations, split into lattice building and inference),
// and network + CRF per keyframe at the frame's resolution (640x480 out). Threads: [onnx] threads =
// 2 (process-wide OpenCV thread pool).
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "smap/core/TrackedConfig.h"
#include "smap/segmentation/CrfSegmenter.h"
#include "smap/segmentation/OnnxSegmenter.h"
#include "smap/segmentation/PermutohedralLattice.h"
#include "smap/segmentation/SegmentationParameters.h"

namespace
{
using namespace smap;

segmentation::SegmentationParameters shippedParameters()
{
    core::TrackedConfig cfg;
    cfg.loadFile(std::string(SMAP_SOURCE_DIR) + "/config/espnetv2_voc.ini");
    segmentation::SegmentationParameters p;
    cfg.load(p);
    // The shipped path is relative to the repository root; benchmarks run from anywhere.
    p.onnx.model =
        std::string(SMAP_SHARED_DIR) + "/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx";
    return p;
}

core::RgbdFrame kitchenFrame(int index)
{
    core::RgbdFrame f;
    f.colour = cv::imread(std::string(SMAP_SHARED_DIR) +
                          cv::format("/data/7scenes-redkitchen/rgb/frame-%06d.jpg", index));
    f.name = std::to_string(index);
    if (f.colour.empty())
        throw std::runtime_error("7-Scenes frames not found under " SMAP_SHARED_DIR);
    return f;
}

void BM_Network320x240(benchmark::State& state)
{
    const auto p = shippedParameters();
    segmentation::OnnxSegmenter seg(p.onnx, segmentation::loadLabelSet(p));
    seg.setMinLoggingLevel(mrpt::system::LVL_WARN);
    const auto frame = kitchenFrame(200);
    for (auto _ : state)
        benchmark::DoNotOptimize(seg.segmentNative(frame));
}

void BM_NetworkForwardOnly(benchmark::State& state)
{
    const auto p = shippedParameters();
    segmentation::OnnxSegmenter seg(p.onnx, segmentation::loadLabelSet(p));
    seg.setMinLoggingLevel(mrpt::system::LVL_WARN);
    const auto frame = kitchenFrame(200);
    for (auto _ : state)
        benchmark::DoNotOptimize(seg.forward(frame.colour));
}

void BM_UpsampleTo640x480(benchmark::State& state)
{
    const auto p = shippedParameters();
    segmentation::OnnxSegmenter seg(p.onnx, segmentation::loadLabelSet(p));
    seg.setMinLoggingLevel(mrpt::system::LVL_WARN);
    const auto r = seg.segmentNative(kitchenFrame(200));
    for (auto _ : state)
        benchmark::DoNotOptimize(r.resized(640, 480));
}

void BM_Crf320x240(benchmark::State& state)
{
    const auto p = shippedParameters();
    segmentation::OnnxSegmenter seg(p.onnx, segmentation::loadLabelSet(p));
    seg.setMinLoggingLevel(mrpt::system::LVL_WARN);
    const auto frame = kitchenFrame(200);
    const auto r = seg.segmentNative(frame);
    cv::Mat small;
    cv::resize(frame.colour, small, cv::Size(r.width(), r.height()), 0, 0, cv::INTER_AREA);
    segmentation::DenseCrf crf(p.crf, r.labelCount());
    for (auto _ : state)
        benchmark::DoNotOptimize(crf.refine(small, r.probabilities));
    state.counters["labels"] = r.labelCount();
    state.counters["iterations"] = p.crf.iterations;
}

void BM_LatticeBuild320x240(benchmark::State& state)
{
    const auto p = shippedParameters();
    const auto frame = kitchenFrame(200);
    cv::Mat small;
    cv::resize(frame.colour, small, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    const segmentation::DenseCrf crf(p.crf, 21);
    const cv::Mat features =
        state.range(0) == 5 ? crf.appearanceFeatures(small) : crf.smoothnessFeatures(320, 240);
    int vertices = 0;
    for (auto _ : state)
    {
        const segmentation::PermutohedralLattice lattice(features);
        vertices = lattice.vertexCount();
    }
    state.counters["vertices"] = vertices;
}

void BM_NetworkPlusCrfPerKeyframe(benchmark::State& state)
{
    const auto p = shippedParameters();
    auto seg = segmentation::makeSegmenter(p);
    seg->setMinLoggingLevel(mrpt::system::LVL_WARN);
    const auto frame = kitchenFrame(200);
    for (auto _ : state)
        benchmark::DoNotOptimize(seg->segment(frame));
}
}  // namespace

BENCHMARK(BM_Network320x240)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NetworkForwardOnly)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_UpsampleTo640x480)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Crf320x240)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LatticeBuild320x240)->Arg(5)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NetworkPlusCrfPerKeyframe)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
