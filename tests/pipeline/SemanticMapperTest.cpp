// SemanticMapper, the embeddable runtime: every stage's time reaches its profiler.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <map>
#include <thread>

#include "smap/pipeline/SemanticMapper.h"
#include "smap/segmentation/SegmentationParameters.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;

namespace
{
/// A segmenter that answers only once the test opens its gate (a segmentation far slower than
/// tracking); every pixel is class 0 (background).
class GatedSegmenter : public segmentation::Segmenter
{
public:
    GatedSegmenter(core::LabelSet labels, std::shared_future<void> gate)
        : Segmenter("gated", std::move(labels)), gate_(std::move(gate))
    {
    }
    segmentation::SegmentationResult segmentNative(const core::RgbdFrame&) override
    {
        gate_.wait();
        constexpr int kWidth = 32, kHeight = 24;
        cv::Mat probabilities(static_cast<int>(labels().size()), kWidth * kHeight, CV_32FC1,
                              cv::Scalar(0.0F));
        probabilities.row(0).setTo(1.0F);
        return segmentation::SegmentationResult::fromProbabilities(probabilities, kWidth, kHeight);
    }
    std::string description() const override { return "gated"; }

private:
    std::shared_future<void> gate_;
};

/// Opens the gate when it goes out of scope, so that a failed assertion cannot leave the
/// mapper's worker blocked while the mapper is destroyed.
struct GateOpener
{
    std::promise<void>& gate;
    bool opened = false;
    void open()
    {
        if (!opened)
            gate.set_value();
        opened = true;
    }
    ~GateOpener() { open(); }
};
}  // namespace

TEST(SemanticMapper, EveryStageIsTimedInTheProfiler)
{
    sim::GeneratorOptions o;
    o.preset = "static_xyz";
    sim::SequenceGenerator gen(o);
    pipeline::SemanticMapperParameters params;
    params.segmentation.backend = "none";  // no model needed: every pixel void
    params.pipeline.snapshots = false;
    pipeline::SemanticMapper mapper(params);
    mapper.setLoggingLevel(mrpt::system::LVL_ERROR);
    constexpr size_t kFrames = 20;
    for (size_t i = 0; i < kFrames; i++)
    {
        mapper.process(gen.rgbdFrame(i));
    }
    mapper.finish();
    std::map<std::string, mrpt::system::CTimeLogger::TCallStats> stats;
    mapper.profiler().getStats(stats);
    for (const char* stage :
         {"frame.extraction", "frame.dynamic", "frame.tracking", "frame.tracking.optimisation"})
    {
        ASSERT_EQ(stats.count(stage), 1u) << stage;
        EXPECT_EQ(stats[stage].n_calls, kFrames) << stage;
        EXPECT_GE(stats[stage].min_t, 0.0) << stage;
    }
    EXPECT_GT(stats["frame.extraction"].total_t, 0.0);
    const size_t keyframes = mapper.worker().stats().keyframes;
    ASSERT_GT(keyframes, 0u);
    for (const char* stage :
         {"keyframe.segmentation", "keyframe.association", "keyframe.insertion"})
    {
        ASSERT_EQ(stats.count(stage), 1u) << stage;
        EXPECT_EQ(stats[stage].n_calls, keyframes) << stage;
    }
}

// Tracking never waits for segmentation. With the default configuration, frames go
// on being tracked while no keyframe has been segmented (no mask, no wait); once the
// segmentation answers, later frames use its mask and report how old it is.
TEST(SemanticMapper, TrackingNeverWaitsForALateSegmentation)
{
    sim::GeneratorOptions o;
    o.preset = "static_xyz";
    sim::SequenceGenerator gen(o);
    pipeline::SemanticMapperParameters params;
    params.segmentation.backend = "none";
    params.pipeline.snapshots = false;
    ASSERT_EQ(params.semanticEvidence.mask_latency_s, 0.0);
    std::promise<void> gate;
    pipeline::SemanticMapper mapper(
        params, std::make_unique<GatedSegmenter>(segmentation::loadLabelSet(params.segmentation),
                                                 gate.get_future().share()));
    mapper.setLoggingLevel(mrpt::system::LVL_ERROR);
    GateOpener opener{gate};
    // 60 frames: past the 20-frame latency a reproducible run would wait at.
    constexpr size_t kClosed = 60;
    size_t tracked = 0;
    for (size_t i = 0; i < kClosed; i++)
    {
        const auto r = mapper.process(gen.rgbdFrame(i));
        EXPECT_EQ(r.mask_wait_ms, 0.0) << "frame " << i;
        EXPECT_FALSE(r.maskAge.has_value()) << "frame " << i;
        tracked += slam::hasPose(r.tracking.status) ? 1 : 0;
    }
    EXPECT_GE(tracked, kClosed - 1);
    ASSERT_GT(mapper.keyframesSubmitted(), 0u);
    EXPECT_EQ(mapper.worker().stats().keyframes, 0u);  // none segmented yet
    opener.open();
    // The first mask arrives some frames later, in the worker's own time.
    std::optional<uint64_t> age;
    for (size_t i = kClosed; i < 300 && !age; i++)
    {
        const auto r = mapper.process(gen.rgbdFrame(i));
        EXPECT_EQ(r.mask_wait_ms, 0.0) << "frame " << i;
        age = r.maskAge;
        if (!age)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_TRUE(age.has_value()) << "no frame used a mask";
    EXPECT_GE(*age, 1u);
    mapper.finish();
}

// Time parameters count seconds of the recording: frames whose timestamps do not increase are
// taken 1/30 s apart, so that keyframes are still made at least every second.
TEST(SemanticMapper, FramesWithoutIncreasingTimestampsAreTakenANominalIntervalApart)
{
    sim::GeneratorOptions o;
    o.preset = "static_xyz";
    sim::SequenceGenerator gen(o);
    pipeline::SemanticMapperParameters params;
    params.segmentation.backend = "none";
    params.tracking.keyframe_min_interval_s = 0.0;
    params.tracking.keyframe_ref_ratio = 0.01;  // keyframes by time only
    pipeline::SemanticMapper mapper(params);
    mapper.setLoggingLevel(mrpt::system::LVL_ERROR);
    constexpr size_t kFrames = 70;
    for (size_t i = 0; i < kFrames; i++)
    {
        core::RgbdFrame f = gen.rgbdFrame(i);
        f.timestamp = 7.0;  // a source that stamps every frame alike
        mapper.process(f);
    }
    mapper.finish();
    const core::Trajectory t = mapper.trajectory();
    ASSERT_EQ(t.size(), kFrames);
    EXPECT_DOUBLE_EQ(t.front().timestamp, 7.0);
    for (size_t i = 1; i < t.size(); ++i)
        EXPECT_NEAR(t[i].timestamp - t[i - 1].timestamp, 1.0 / 30.0, 1e-9) << i;
    // Keyframe at frame 0, then one a second: frames 30 and 60.
    EXPECT_GE(mapper.keyFrameTrajectory().size(), 3u);
}
