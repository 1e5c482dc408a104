// Hand-made frames for map bookkeeping tests: keypoints in a row with depth, no image.
#pragma once

#include "smap/slam/Frame.h"

namespace smap::test
{
/// `n` keypoints at (10 + i, 20), level 0, 2 m deep, zero descriptors, weight 1, at the pose.
inline slam::Frame frameWithKeypoints(size_t n, const Eigen::Isometry3d& T_cam_world)
{
    slam::Frame f;
    f.features.pyramid = features::ScalePyramid::make(8, 1.2);
    for (size_t i = 0; i < n; ++i)
    {
        cv::KeyPoint kp(static_cast<float>(10 + i), 20.0F, 31);
        kp.octave = 0;
        f.features.keypoints.push_back(kp);
        f.features.undistorted.push_back(kp.pt);
        f.features.depth.push_back(2.0F);
        f.features.rightU.push_back(kp.pt.x - 20.0F);
    }
    f.features.descriptors = cv::Mat::zeros(static_cast<int>(n), 32, CV_8UC1);
    f.weights.assign(n, 1.0F);
    f.clearMatches();
    f.T_cam_world = T_cam_world;
    return f;
}
}  // namespace smap::test
