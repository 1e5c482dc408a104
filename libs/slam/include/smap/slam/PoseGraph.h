// Pose-graph optimisation over keyframes (loop correction): each edge holds a measured relative
// pose between two keyframes, and the poses move so that all edges agree as well as they can.
// RGB-D gives metric scale, so the poses are rigid (SE(3)), not similarities.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

namespace smap::slam
{
struct PoseGraphEdge
{
    uint64_t i = 0, j = 0;
    /// Measured T_cam_i * T_cam_j^-1 (T = T_cam_world): camera j's frame into camera i's.
    Eigen::Isometry3d T_i_j = Eigen::Isometry3d::Identity();
    double weight = 1.0;
};

struct PoseGraphResult
{
    int iterations = 0;
    double initialCost = 0.0;
    double finalCost = 0.0;
};

/// Optimises every T_cam_world in `poses` (by keyframe id) over `edges` (edges naming a pose
/// that is not there are ignored); the `fixed` ones hold still (at least one must be given).
/// Residual per edge: the rotation (angle, radians) and translation (m) of
/// T_i_j^-1 * T_i * T_j^-1, times the edge weight.
PoseGraphResult optimisePoseGraph(std::map<uint64_t, Eigen::Isometry3d>& poses,
                                  const std::vector<PoseGraphEdge>& edges,
                                  const std::set<uint64_t>& fixed, int max_iterations);
}  // namespace smap::slam
