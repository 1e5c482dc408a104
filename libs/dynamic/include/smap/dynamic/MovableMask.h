// Semantic evidence for tracking: the pixels of a keyframe that segmentation gave a movable
// class (a person), kept as 3-D samples in the keyframe's camera frame so that they can be
// warped into any later frame by its pose. A person who stands still stays where the warp puts
// them; one who walks drifts from it, which the dilation (growing with the mask's age) and the
// flow test cover, or without() leaves them out.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::dynamic
{
/// A warped mask on a grid of kCell x kCell pixel cells, with the nearest depth the movable
/// samples have there (grown with the cells, so that growing takes in what lies at the
/// people's depth and not the background behind them).
struct MovableCells
{
    static constexpr int kCell = 8;
    cv::Mat cells;    ///< CV_8UC1, ceil(height / kCell) x ceil(width / kCell); empty: none
    cv::Mat nearest;  ///< CV_32FC1, per cell: the nearest sample depth around it (m)

    bool empty() const { return cells.empty(); }
    /// Whether the pixel (u, v) with depth z (m; <= 0: unknown, the cell alone decides) lies in
    /// a movable cell, within `margin` of the nearest sample depth around it (a mask's edge
    /// often takes in background behind; false outside the grid).
    bool contains(float u, float v, float z, float margin) const;
    /// The fraction of the grid's cells that are movable.
    double coverage() const;
};

class MovableMask
{
public:
    MovableMask() = default;
    /// `labels` CV_8UC1 class ids, `depth` CV_32FC1 metres (0 = none), both of `camera`'s size;
    /// `movable[id]` marks the movable classes (ids beyond its size are not). One sample every
    /// `step` pixels each way; a movable pixel without depth takes the median depth of the
    /// movable pixels with one.
    MovableMask(uint64_t frameId, const Eigen::Isometry3d& T_world_cam, const cv::Mat& labels,
                const cv::Mat& depth, const core::PinholeCamera& camera,
                const std::vector<bool>& movable, int step);

    uint64_t frameId() const { return frameId_; }
    /// CV_8UC1 at the keyframe's resolution: 255 on movable-class pixels.
    const cv::Mat& image() const { return image_; }
    bool empty() const { return points_cam_.empty(); }
    size_t samples() const { return points_cam_.size(); }

    /// The same mask without the pixels non-zero in `drop` (CV_8UC1 at the keyframe's
    /// resolution).
    MovableMask without(const cv::Mat& drop) const;

    /// The mask seen from a camera at T_world_cam (`camera`'s size), grown by `dilationPx`
    /// (cells and depth ranges).
    MovableCells project(const Eigen::Isometry3d& T_world_cam, const core::PinholeCamera& camera,
                         double dilationPx) const;

private:
    uint64_t frameId_ = 0;
    cv::Mat image_;
    Eigen::Isometry3d T_world_keyframe_ = Eigen::Isometry3d::Identity();
    std::vector<Eigen::Vector3f> points_cam_;  ///< in the keyframe's camera frame
    std::vector<float> footprint_;             ///< px each sample covers in the keyframe (x z)
    std::vector<cv::Point> pixels_;            ///< where each sample is in the keyframe
};
}  // namespace smap::dynamic
