#include "smap/dynamic/MovableMask.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "smap/core/Median.h"

namespace smap::dynamic
{
bool MovableCells::contains(float u, float v, float z, float margin) const
{
    if (cells.empty() || !(u >= 0.0F) || !(v >= 0.0F))
        return false;
    const int cx = static_cast<int>(u) / kCell, cy = static_cast<int>(v) / kCell;
    if (cx >= cells.cols || cy >= cells.rows || cells.at<uint8_t>(cy, cx) == 0)
        return false;
    // Behind the nearest sample only: a mask's edge often takes in some background.
    return !(z > 0.0F) ||
           (z >= nearest.at<float>(cy, cx) - margin && z <= nearest.at<float>(cy, cx) + margin);
}

double MovableCells::coverage() const
{
    if (cells.empty())
        return 0.0;
    return static_cast<double>(cv::countNonZero(cells)) / static_cast<double>(cells.total());
}

namespace
{
bool isMovable(const std::vector<bool>& movable, uint8_t label)
{
    return label < movable.size() && movable[label];
}

/// The median depth of the movable pixels with depth, sampled every `step` px (0 when none).
float medianMovableDepth(const cv::Mat& labels, const cv::Mat& depth,
                         const std::vector<bool>& movable, int step)
{
    std::vector<float> z;
    for (int v = step / 2; v < labels.rows; v += step)
        for (int u = step / 2; u < labels.cols; u += step)
            if (isMovable(movable, labels.at<uint8_t>(v, u)) && depth.at<float>(v, u) > 0.0F)
                z.push_back(depth.at<float>(v, u));
    return core::upperMedianInPlace(z, 0.0F);
}
}  // namespace

MovableMask::MovableMask(uint64_t frameId, const Eigen::Isometry3d& T_world_cam,
                         const cv::Mat& labels, const cv::Mat& depth,
                         const core::PinholeCamera& camera, const std::vector<bool>& movable,
                         int step)
    : frameId_(frameId), T_world_keyframe_(T_world_cam)
{
    CV_Assert(labels.type() == CV_8UC1 && depth.type() == CV_32FC1 &&
              labels.size() == depth.size() && step >= 1);
    image_ = cv::Mat::zeros(labels.size(), CV_8UC1);
    for (int v = 0; v < labels.rows; ++v)
        for (int u = 0; u < labels.cols; ++u)
            if (isMovable(movable, labels.at<uint8_t>(v, u)))
                image_.at<uint8_t>(v, u) = 255;
    const float fallback = medianMovableDepth(labels, depth, movable, step);
    for (int v = step / 2; v < labels.rows; v += step)
    {
        for (int u = step / 2; u < labels.cols; u += step)
        {
            if (!isMovable(movable, labels.at<uint8_t>(v, u)))
                continue;
            float z = depth.at<float>(v, u);
            if (!(z > 0.0F))
                z = fallback;
            if (!(z > 0.0F))
                continue;
            points_cam_.push_back(camera.unproject(u, v, z).cast<float>());
            footprint_.push_back(static_cast<float>(step) * z);
            pixels_.emplace_back(u, v);
        }
    }
}

MovableMask MovableMask::without(const cv::Mat& drop) const
{
    CV_Assert(drop.type() == CV_8UC1 && drop.size() == image_.size());
    MovableMask kept;
    kept.frameId_ = frameId_;
    kept.T_world_keyframe_ = T_world_keyframe_;
    kept.image_ = image_.clone();
    kept.image_.setTo(0, drop);
    for (size_t i = 0; i < pixels_.size(); ++i)
    {
        if (drop.at<uint8_t>(pixels_[i]) != 0)
            continue;
        kept.points_cam_.push_back(points_cam_[i]);
        kept.footprint_.push_back(footprint_[i]);
        kept.pixels_.push_back(pixels_[i]);
    }
    return kept;
}

MovableCells MovableMask::project(const Eigen::Isometry3d& T_world_cam,
                                  const core::PinholeCamera& camera, double dilationPx) const
{
    MovableCells out;
    if (points_cam_.empty())
        return out;
    constexpr int kCell = MovableCells::kCell;
    const int rows = (camera.height + kCell - 1) / kCell, cols = (camera.width + kCell - 1) / kCell;
    out.cells = cv::Mat::zeros(rows, cols, CV_8UC1);
    out.nearest = cv::Mat(rows, cols, CV_32FC1, cv::Scalar(std::numeric_limits<float>::max()));
    const Eigen::Isometry3f T_cam_keyframe =
        (T_world_cam.inverse() * T_world_keyframe_).cast<float>();
    bool any = false;
    for (size_t i = 0; i < points_cam_.size(); ++i)
    {
        const Eigen::Vector3f p = T_cam_keyframe * points_cam_[i];
        if (p.z() < 0.05F)
            continue;
        const Eigen::Vector2d uv = camera.project(p.cast<double>());
        // Half the sample's footprint at its new distance: a person now closer covers more.
        const double half = 0.5 * footprint_[i] / p.z();
        const int u0 = static_cast<int>(std::floor((uv.x() - half) / kCell));
        const int u1 = static_cast<int>(std::floor((uv.x() + half) / kCell));
        const int v0 = static_cast<int>(std::floor((uv.y() - half) / kCell));
        const int v1 = static_cast<int>(std::floor((uv.y() + half) / kCell));
        for (int cy = std::max(v0, 0); cy <= std::min(v1, out.cells.rows - 1); ++cy)
        {
            for (int cx = std::max(u0, 0); cx <= std::min(u1, out.cells.cols - 1); ++cx)
            {
                out.cells.at<uint8_t>(cy, cx) = 255;
                float& nearest = out.nearest.at<float>(cy, cx);
                nearest = std::min(nearest, p.z());
                any = true;
            }
        }
    }
    if (!any)
        return {};
    const int radius = static_cast<int>(std::ceil(dilationPx / kCell));
    if (radius > 0)
    {
        const cv::Mat disc =
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
        cv::dilate(out.cells, out.cells, disc);
        cv::erode(out.nearest, out.nearest, disc);  // min filter
    }
    return out;
}
}  // namespace smap::dynamic
