// The one place where a frame source puts depth on the colour camera's grid. Every source (TUM
// folders with a [depth_camera], rawlogs whose observations carry two cameras) hands it the depth
// image in metres on the depth camera's grid, both cameras and the depth-to-colour extrinsic; it
// returns the depth the rest of semantic-mapper expects: z in the colour camera's optical frame,
// one value per colour pixel. The registration (per-pixel rays) is built once and rebuilt only
// when the cameras or the extrinsic change.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core/mat.hpp>

#include "smap/core/PinholeCamera.h"

namespace smap::io
{
class DepthRegistration;

class DepthToColour
{
public:
    DepthToColour();
    ~DepthToColour();
    DepthToColour(DepthToColour&&) noexcept;
    DepthToColour& operator=(DepthToColour&&) noexcept;

    /// `depth`: CV_32FC1 metres on `depthCamera`'s grid (0 = invalid). `T_colour_depth` maps
    /// points from the depth camera's optical frame to the colour camera's. When the two cameras
    /// coincide (same intrinsics, isIdentity(T_colour_depth)) `depth` is returned as it is.
    cv::Mat onColourGrid(const cv::Mat& depth, const core::PinholeCamera& depthCamera,
                         const core::PinholeCamera& colourCamera,
                         const Eigen::Isometry3d& T_colour_depth);

private:
    struct Cache;
    std::unique_ptr<Cache> cache_;
};

/// Same size, intrinsics and distortion (to 1e-9).
bool sameIntrinsics(const core::PinholeCamera& a, const core::PinholeCamera& b);
/// Rotation and translation (m) within 1e-6 of the identity.
bool isIdentity(const Eigen::Isometry3d& T);
}  // namespace smap::io
