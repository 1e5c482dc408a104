// Where a keypoint seen by two keyframes lies: from its depth, or triangulated from the two
// rays when they cross at a sharper angle than the depth's virtual stereo pair sees it (ORB-SLAM's
// rule for new points).
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace smap::slam
{
class KeyFrame;

/// Keypoint `i` of `a` and keypoint `j` of `b`, the same point; `p_depth` is where a's depth puts
/// it. Returns the two-ray triangulation when the rays' parallax is larger than that of a's
/// virtual baseline at its depth (and above 0.01 deg), else `p_depth`.
Eigen::Vector3d twoViewPosition(const KeyFrame& a, size_t i, const KeyFrame& b, size_t j,
                                const Eigen::Vector3d& p_depth);
}  // namespace smap::slam
