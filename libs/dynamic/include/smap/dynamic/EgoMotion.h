// Camera motion between two consecutive frames from their features: the paper's five-point
// essential matrix (RANSAC), with the metric scale of the translation taken from depth.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/dynamic/DynamicParameters.h"
#include "smap/features/FeatureSet.h"

namespace smap::dynamic
{
struct EgoMotion
{
    bool valid = false;
    /// Maps points from the previous camera's optical frame into the current one's.
    Eigen::Isometry3d T_cur_prev = Eigen::Isometry3d::Identity();
    int matches = 0;         ///< descriptor matches fed to RANSAC
    int inliers = 0;         ///< RANSAC inliers
    int scaleSamples = 0;    ///< matches the metric scale was taken from (depth PnP: with depth)
    bool fromPrior = false;  ///< depth PnP: the prior won over (or stood in for) RANSAC
};

/// Five-point RANSAC on ratio-test descriptor matches (undistorted pixels), the relative pose
/// from the essential matrix, then the translation's length from depth: the median over
/// inliers of the 3D-3D estimate (both depths) or, failing that, of the reprojection estimate
/// (previous depth only). Invalid with fewer than 8 matches.
EgoMotion estimateEgoMotionFivePoint(const features::FeatureSet& previous,
                                     const features::FeatureSet& current,
                                     const core::PinholeCamera& camera,
                                     const DynamicParameters& params);
/// Beyond the paper: the same matches, but the previous keypoints' depth makes them 3D points
/// and PnP-RANSAC (AP3P minimal samples, `pnp_threshold` px) gives a metric pose directly;
/// with `refine`, the inliers are then re-selected under the pose and the pose fitted to all
/// of them (`refinePose`), three rounds. Better conditioned than the five-point
/// method over a short baseline. Matches at most `ego_max_queries` current keypoints (all of
/// them when those give fewer than 60 matches with depth); previous keypoints marked in
/// `previous_dynamic` (when it has one entry per previous keypoint) are never matched, so that
/// movers filling most of the view cannot outvote the background. A `prior` motion (e.g. the
/// previous frame's) competes with the RANSAC pose: the one that more matches reproject within
/// 3 x pnp_threshold of wins, and the prior stands in when RANSAC fails (`fromPrior`). Without
/// a prior, invalid with fewer than 12 matches with depth or 12 inliers.
EgoMotion estimateEgoMotionDepthPnp(const features::FeatureSet& previous,
                                    const features::FeatureSet& current,
                                    const core::PinholeCamera& camera,
                                    const DynamicParameters& params, bool refine = true,
                                    const std::vector<bool>& previous_dynamic = {},
                                    const std::optional<Eigen::Isometry3d>& prior = std::nullopt);

/// Least-squares pose from 3D points (`points_source`, in a source camera's optical frame) and
/// where a target camera sees them (`pixels_target`, undistorted pixels): Gauss-Newton on the
/// squared reprojection error from `T_target_source`, at most `max_iterations` steps. Empty
/// with fewer than 6 pairs, a point behind the camera or a singular system. A few hundred
/// pairs take tens of microseconds, a fraction of cv::solvePnP's iterative solver.
std::optional<Eigen::Isometry3d> refinePose(const std::vector<Eigen::Vector3d>& points_source,
                                            const std::vector<Eigen::Vector2d>& pixels_target,
                                            const core::PinholeCamera& camera,
                                            const Eigen::Isometry3d& T_target_source,
                                            int max_iterations = 10);
}  // namespace smap::dynamic
