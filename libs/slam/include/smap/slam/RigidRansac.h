// The rigid motion between two sets of corresponding 3D points (loop verification with depth):
// RANSAC over minimal three-point samples, then a least-squares refit on the inliers.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

namespace smap::slam
{
struct RigidEstimate
{
    Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  ///< a ~ T_a_b * b
    std::vector<size_t> inliers;                              ///< pair indices, increasing
};

/// T_a_b from pairs (a[k], b[k]); a pair is an inlier when |a - T_a_b b| <= tolerance[k]
/// (depth noise grows with distance, so each pair has its own). `iterations` samples drawn from
/// a generator seeded with `seed` (deterministic). Nothing when fewer than 3 pairs or fewer
/// than `min_inliers` inliers.
std::optional<RigidEstimate> estimateRigidRansac(const std::vector<Eigen::Vector3d>& a,
                                                 const std::vector<Eigen::Vector3d>& b,
                                                 const std::vector<double>& tolerance,
                                                 int min_inliers, int iterations, uint32_t seed);
}  // namespace smap::slam
