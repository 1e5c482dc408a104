// ORB-SLAM's rotation consistency check: between two views the keypoint orientation of every
// true match changes by about the same angle, so matches outside the dominant bins of a
// histogram of angle changes are rejected.
#pragma once

#include <cstddef>
#include <vector>

namespace smap::features
{
class RotationConsistency
{
public:
    explicit RotationConsistency(int bins = 30) : bins_(bins), hist_(static_cast<size_t>(bins)) {}

    /// Records match `id` whose keypoints have orientations angle_a and angle_b (degrees).
    void add(size_t id, float angle_a, float angle_b);
    /// Ids of matches outside the three most populated bins (bins under 10% of the
    /// largest do not count as dominant).
    std::vector<size_t> inconsistent() const;

private:
    int bins_;
    std::vector<std::vector<size_t>> hist_;
};
}  // namespace smap::features
