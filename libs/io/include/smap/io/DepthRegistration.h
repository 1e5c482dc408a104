// Re-expresses a depth image taken by one camera on the pixel grid of another (the colour
// camera), for RGB-D sensors whose depth and colour cameras do not coincide (e.g. MRPT Kinect
// rawlogs with relativePoseIntensityWRTDepth != identity).
#pragma once

#include <Eigen/Geometry>
#include <array>
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
    /// Where each pixel of one depth row (pixels first .. first + cols - 1) lands: colour
    /// column + 0.5, row + 0.5 and depth in the colour frame (meaningless where depth <= 0).
    void projectRow(const float* depth, size_t first, size_t cols, float* us, float* vs,
                    float* zs) const;
    /// Keeps the nearest depth per colour pixel, of the row's valid depth pixels in front of
    /// the colour camera.
    void scatterRow(const float* depth, const float* us, const float* vs, const float* zs,
                    size_t cols, float* dst) const;

    core::PinholeCamera depthCamera_;
    core::PinholeCamera colourCamera_;
    Eigen::Isometry3d T_colour_depth_;
    std::vector<cv::Point2f> rays_;
    /// R_colour_depth * (x/z, y/z, 1) of each depth pixel, one array per component: its point
    /// at depth z is z * rotatedRays_[.][i] + t_colour_depth in the colour frame.
    std::array<std::vector<float>, 3> rotatedRays_;
    bool colourDistorted_ = false;
    float fx_, fy_, cx_, cy_, width_, height_;  ///< the colour camera's, as floats
};

/// Undistorted normalised coordinates of every pixel of `camera`, row-major.
std::vector<cv::Point2f> undistortedPixelRays(const core::PinholeCamera& camera);
}  // namespace smap::io
