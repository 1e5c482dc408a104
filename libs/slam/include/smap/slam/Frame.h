// A frame as tracking sees it: its features, their per-keypoint weights (the outside feature
// mask), the map points they matched and the estimated camera pose.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/features/FeatureGrid.h"
#include "smap/features/FeatureSet.h"

namespace smap::slam
{
class MapPoint;

struct Frame
{
    uint64_t id = 0;  ///< position in the processed sequence
    double timestamp = 0.0;
    core::PinholeCamera camera;
    double bf = 0.0;          ///< virtual baseline x fx
    double closeDepth = 0.0;  ///< m
    features::FeatureSet features;
    features::FeatureGrid grid;  ///< over the undistorted keypoints
    /// Per keypoint, in [0, 1]: 0 excludes the keypoint from tracking and mapping (e.g. a
    /// dynamic point), values in between scale its weight in the optimisation.
    std::vector<float> weights;
    /// Per keypoint (empty: every usable one): may start a new map point at a keyframe. The
    /// dynamic filter clears it where it could not measure the flow: such a keypoint is used
    /// for tracking, but nothing shows that it is static.
    std::vector<bool> mappable;
    /// Per keypoint (empty: none): on a region of a movable class (semantic evidence). Such a
    /// keypoint has weight 0 that only the last fallback raises: a person is not a landmark,
    /// moving or not.
    std::vector<bool> movable;
    /// Per keypoint (empty: none): movable, and found still by the motion evidence. The last
    /// tracking fallback (TrackingFallback::StillMovable) lets these carry a little weight;
    /// they never start map points.
    std::vector<bool> stillMovable;
    std::vector<std::shared_ptr<MapPoint>> points;  ///< matched map point or null
    std::vector<bool> outlier;
    Eigen::Isometry3d T_cam_world = Eigen::Isometry3d::Identity();
    cv::Mat thumbnail;  ///< small, blurred, zero-mean unit-norm image for relocalisation
    /// Outside odometry (optional, e.g. the dynamic filter's ego-motion): this camera's pose
    /// relative to the camera `odometryFramesBack` frames earlier. While tracking is lost it
    /// carries the pose forward, so that a re-anchored map starts where the camera is.
    std::optional<Eigen::Isometry3d> odometry_T_cam_earlier;
    uint64_t odometryFramesBack = 0;

    size_t size() const { return features.size(); }
    bool usable(size_t i) const { return weights[i] > 0.0F; }
    bool canMap(size_t i) const { return usable(i) && (mappable.empty() || mappable[i]); }
    /// Indices of the keypoints with weight > 0.
    std::vector<size_t> usableKeypoints() const;
    /// Sets per-keypoint weights; an empty vector means all 1. Throws std::invalid_argument
    /// when the size does not match or a weight is outside [0, 1].
    void setWeights(const std::vector<float>& w);
    /// Sets `mappable` (empty: all); throws std::invalid_argument when the size does not match.
    void setMappable(const std::vector<bool>& m);
    /// Weights from a mask image on the colour image's grid: 0 where mask == 0.
    void setMask(const cv::Mat& mask);
    void clearMatches();
    /// Drops the matches flagged as outliers; returns the remaining matches whose map point
    /// is in the map (has observations).
    int discardOutliers();
    int countMatches() const;  ///< non-outlier matches to map points
};

/// Small normalised image used to rank keyframes for relocalisation.
cv::Mat makeThumbnail(const cv::Mat& image);
/// Zero-mean normalised cross-correlation of two thumbnails, in [-1, 1].
double thumbnailSimilarity(const cv::Mat& a, const cv::Mat& b);
}  // namespace smap::slam
