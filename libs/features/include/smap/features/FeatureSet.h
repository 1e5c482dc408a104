// The ORB features of one frame: keypoints, descriptors, and per-keypoint depth as an RGB-D
// tracker needs them (metric depth and a virtual right-image coordinate, as ORB-SLAM does).
#pragma once

#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::features
{
/// Scale of every pyramid level and the measurement variance that goes with it.
struct ScalePyramid
{
    std::vector<float> scale;      ///< scale[l] = factor^l
    std::vector<float> invSigma2;  ///< 1 / scale[l]^2: information of a pixel measurement
    float scaleFactor = 1.2F;
    float logScaleFactor = 0.0F;

    static ScalePyramid make(int levels, double factor);
    int levels() const { return static_cast<int>(scale.size()); }
};

struct FeatureSet
{
    /// Keypoints in level-0 pixels of the (possibly distorted) image; `octave` is the level,
    /// `angle` the orientation in degrees.
    std::vector<cv::KeyPoint> keypoints;
    /// Undistorted level-0 pixel coordinates, used for all geometry.
    std::vector<cv::Point2f> undistorted;
    cv::Mat descriptors;  ///< N x 32, CV_8U (256-bit binary descriptors)
    /// Depth (m, optical z) at each keypoint; 0 where the depth image has none.
    std::vector<float> depth;
    /// Virtual right-camera column u - bf / z; negative where there is no depth.
    std::vector<float> rightU;
    ScalePyramid pyramid;

    size_t size() const { return keypoints.size(); }
    const uint8_t* descriptor(size_t i) const
    {
        return descriptors.ptr<uint8_t>(static_cast<int>(i));
    }
    bool hasDepth(size_t i) const { return depth[i] > 0.0F; }
};

/// Fills `undistorted` from `keypoints` with the camera's distortion model (a copy when none).
void undistortKeypoints(FeatureSet& features, const core::PinholeCamera& camera);

/// Fills `depth` and `rightU` from a depth image registered to the colour image (CV_32FC1,
/// metres, 0 = invalid). Depths outside [min_depth, max_depth] count as missing, and so do
/// depths on a depth discontinuity: when the 5x5 neighbourhood spans more than
/// `edge_ratio` x z (corners sit on object borders, where a slightly misregistered or
/// mixed depth would put the point on the wrong surface). `bf` is the virtual stereo baseline
/// times fx (pixels x metres).
void assignDepth(FeatureSet& features, const cv::Mat& depth, double bf, double min_depth,
                 double max_depth, double edge_ratio);
}  // namespace smap::features
