// Per-frame statistics of an RGB-D recording: what the main job reports until the full
// pipeline runs, and a quick health check of any input.
#pragma once

#include <string>

#include "smap/core/RgbdFrame.h"

namespace smap::pipeline
{
struct FrameStats
{
    size_t index = 0;
    double timestamp = 0.0;
    std::string name;
    double validDepthFraction = 0.0;
    double depthMin = 0.0;     ///< metres, over valid pixels (0 when none)
    double depthMedian = 0.0;  ///< metres, over valid pixels
    double depthMax = 0.0;
    double meanIntensity = 0.0;  ///< 0..255, mean of the grey image
};

FrameStats computeFrameStats(const core::RgbdFrame& frame);
std::string frameStatsCsvHeader();
std::string toCsvRow(const FrameStats& s);
}  // namespace smap::pipeline
