// SemanticMapper, the embeddable runtime: every stage's time reaches its profiler.
#include <gtest/gtest.h>

#include <map>

#include "smap/pipeline/SemanticMapper.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;

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
        const auto f = gen.frame(i);
        core::RgbdFrame frame;
        frame.colour = f.rendered.colour;
        frame.depth = f.rendered.depth;
        frame.camera = o.camera;
        frame.timestamp = f.timestamp;
        mapper.process(frame);
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
