// Relocalisation of a lost frame: keyframes ranked by thumbnail similarity, descriptor matches
// to their map points, PnP-RANSAC, then pose refinement and a projection search for more.
#pragma once

#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
struct Frame;
class Map;

/// Sets frame.T_cam_world and its matches on success. Hold the map mutex. Returns the inlier
/// count of the best candidate (0 when none worked).
int relocaliseFrame(Frame& frame, Map& map, const TrackerParameters& params);
}  // namespace smap::slam
