// Loop correction for LoopCloser: the pose graph over every keyframe with the new loop edge,
// map points moved with the keyframes that observe them, duplicates across the loop fused.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "smap/slam/PoseGraph.h"

namespace smap::slam
{
class KeyFrame;
class Map;

/// A verified loop: the keyframe revisited and where the new keyframe is, seen from it.
struct LoopMatch
{
    std::shared_ptr<KeyFrame> loop;                                 ///< the keyframe revisited
    Eigen::Isometry3d T_cam_world = Eigen::Isometry3d::Identity();  ///< the new keyframe's pose
    int inliers = 0;
    int projectedMatches = 0;
};

struct LoopCorrectionOutcome
{
    Eigen::Isometry3d T_loop_keyframe = Eigen::Isometry3d::Identity();  ///< the loop edge
    int keyframes = 0;  ///< keyframes in the pose graph
    int pointsFused = 0;
    double moved_m = 0.0;  ///< how far the new keyframe moved
    double turned_deg = 0.0;
};

/// A revisit that needs no correction: the loop neighbourhood's points fused into the new
/// keyframe's neighbourhood, the edge kept for later corrections. Takes the map mutex once per
/// keyframe of the fusion, so that tracking waits for one keyframe's share at most; the caller
/// holds local mapping still. Returns the points fused.
int joinConsistentRevisit(Map& map, const std::shared_ptr<KeyFrame>& kf, const LoopMatch& match,
                          std::vector<PoseGraphEdge>& loopEdges, int covisibility_min_weight);

/// Takes the map mutex to copy the graph out and to write the result back, not while solving;
/// the caller holds local mapping still. `loopEdges` (the loops found before) gains this one.
LoopCorrectionOutcome correctLoop(Map& map, const std::shared_ptr<KeyFrame>& kf,
                                  const LoopMatch& match, std::vector<PoseGraphEdge>& loopEdges,
                                  int iterations, int covisibility_min_weight);
}  // namespace smap::slam
