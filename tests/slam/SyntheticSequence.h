// Small rendered RGB-D sequences with exact ground truth for the tracking tests.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "smap/core/RgbdFrame.h"
#include "smap/core/Trajectory.h"
#include "smap/sim/SequenceGenerator.h"

namespace smap::test
{
struct RenderedSequence
{
    std::vector<core::RgbdFrame> frames;
    core::Trajectory groundTruth;
};

/// `n` frames of a preset, sensor-noisy depth; by default at 640x480 (f = 525, the acceptance
/// resolution), otherwise through `camera`.
inline RenderedSequence renderSequence(const std::string& preset, size_t n, uint32_t seed = 1,
                                       const std::optional<core::PinholeCamera>& camera = {})
{
    sim::GeneratorOptions o;
    o.preset = preset;
    o.seed = seed;
    if (camera)
        o.camera = *camera;
    sim::SequenceGenerator gen(o);
    RenderedSequence s;
    for (size_t i = 0; i < n; ++i)
    {
        auto f = gen.frame(i);
        core::RgbdFrame r;
        r.colour = f.rendered.colour;
        r.depth = f.rendered.depth;
        r.camera = o.camera;
        r.timestamp = f.timestamp;
        r.index = i;
        s.frames.push_back(r);
        s.groundTruth.push_back({f.timestamp, f.T_world_cam});
    }
    return s;
}
}  // namespace smap::test
