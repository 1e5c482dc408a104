// Bundle adjustment: local, around a keyframe (its covisible keyframes and every point they see
// are optimised, keyframes that only see those points hold still), and global, over every live
// keyframe and point at the end of a run. Both use a robust cost and remove outlier
// observations between two solves. In both, a keyframe that shares too few observed points with
// the other keyframes of the problem holds the pose tracking gave it. The map mutex is held to copy
// the problem out and to write the result back, never while solving.
#pragma once

#include <atomic>
#include <memory>

#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
class KeyFrame;
class Map;

struct BundleAdjustmentStats
{
    int keyframes = 0;       ///< optimised
    int fixedKeyframes = 0;  ///< held constant
    int weaklyTiedHeld = 0;  ///< of those, held because few of their points are shared
    int points = 0;
    int observations = 0;
    int outliersRemoved = 0;
    bool aborted = false;
};

/// `abort` stops the solver early (tracking wants to insert a keyframe); whatever was reached
/// is still written back.
BundleAdjustmentStats localBundleAdjustment(const std::shared_ptr<KeyFrame>& keyframe, Map& map,
                                            const LocalMappingParameters& params,
                                            const std::atomic<bool>& abort);

/// Every live keyframe and point of the map, the first keyframe (the world frame) held still:
/// `iterations` robust iterations, outlier observations removed, `iterations` more. Frames
/// follow through their reference keyframes. With no first keyframe left (it is never culled)
/// the oldest live keyframe is held instead. A keyframe with fewer than
/// `min_shared_observations` observations of points another keyframe sees too is held as well
/// (`[local_mapping] ba_min_shared_observations`).
BundleAdjustmentStats globalBundleAdjustment(Map& map, int iterations, int min_shared_observations,
                                             const std::atomic<bool>& abort);
}  // namespace smap::slam
