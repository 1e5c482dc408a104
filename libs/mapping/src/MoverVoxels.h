// Where keyframes' movers were, as voxels: the pruning and confirmation near movers
// (SemanticMapBuilder, [map] prune_near_movers, confirm_clear_distance). Private to
// libs/mapping.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_set>

#include "smap/mapping/KeyFrameContribution.h"

namespace smap::mapping
{
class MoverVoxels
{
public:
    /// `edge`: the voxel size (m).
    explicit MoverVoxels(double edge);

    /// c's mover samples at c's pose: the voxels that hold one, and their 26 neighbours.
    void add(const KeyFrameContribution& c);
    /// Whether the world point p lies in one of those voxels (within about one to two edges of
    /// a mover sample).
    bool near(const Eigen::Vector3f& p) const;

private:
    int64_t key(double x, double y, double z) const;

    double edge_;
    std::unordered_set<int64_t> voxels_;
};
}  // namespace smap::mapping
