// Re-expresses a depth image taken by one camera on the pixel grid of another (the colour
// camera), for RGB-D sensors whose depth and colour cameras do not coincide (e.g. MRPT Kinect
// rawlogs with relativePoseIntensityWRTDepth != identity).
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::io
{
class DepthRegistration
{
public:
    /// T_colour_depth maps points from the depth camera's optical frame to the colour camera's.
    DepthRegistration(const core::PinholeCamera& depthCamera,
                      const core::PinholeCamera& colourCamera,
                      const Eigen::Isometry3d& T_colour_depth);

    /// depth: CV_32FC1 metres on the depth camera's grid (0 = invalid). Returns depth (z in the
    /// colour frame) on the colour grid; each depth pixel lands on its nearest colour pixel and
    /// the nearest surface wins. Colour pixels no depth pixel reaches stay 0.
    cv::Mat registerDepth(const cv::Mat& depth) const;

    /// Undistorted normalised ray (x/z, y/z) of each depth pixel, row-major.
    const std::vector<cv::Point2f>& depthRays() const { return rays_; }

private:
    core::PinholeCamera depthCamera_;
    core::PinholeCamera colourCamera_;
    Eigen::Isometry3d T_colour_depth_;
    std::vector<cv::Point2f> rays_;
};

/// Undistorted normalised coordinates of every pixel of `camera`, row-major.
std::vector<cv::Point2f> undistortedPixelRays(const core::PinholeCamera& camera);
}  // namespace smap::io
