// Warp of the previous frame into the current view ("project the last frame onto the current
// frame"), with the previous depth and the relative pose: static surfaces then sit where the
// current frame sees them, so only independently moving things keep a residual flow.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "smap/core/PinholeCamera.h"

namespace smap::dynamic
{
struct WarpedFrame
{
    cv::Mat grey;   ///< CV_8UC1 on the current grid
    cv::Mat depth;  ///< CV_32FC1, depth of the warped surface in the current camera (0 = none)
    cv::Mat valid;  ///< CV_8UC1, 255 where a previous pixel landed (before hole filling)
};

/// Forward-splats every previous pixel with depth into the current camera (nearest surface
/// wins), then fills pinholes up to `fill_passes` pixels wide from their neighbours so that
/// Lucas-Kanade windows see a continuous image.
WarpedFrame warpIntoCurrentView(const cv::Mat& previous_grey, const cv::Mat& previous_depth,
                                const core::PinholeCamera& camera,
                                const Eigen::Isometry3d& T_cur_prev, int fill_passes = 2);
}  // namespace smap::dynamic
