#include "LatestView.h"

#include <mrpt/math/CMatrixFixed.h>

#include <cmath>

namespace smap::mapping
{
cv::Mat LatestView::staticDepthCells(const maps::BackProjector::Images& images, double minDepth,
                                     double maxDepth)
{
    const int cols = (images.depth.cols + kCell - 1) / kCell;
    const int rows = (images.depth.rows + kCell - 1) / kCell;
    cv::Mat nearest(rows, cols, CV_32FC1, cv::Scalar(0.0F));
    cv::Mat observed(rows, cols, CV_32SC1, cv::Scalar(0));
    const auto lo = static_cast<float>(minDepth), hi = static_cast<float>(maxDepth);
    for (int v = 0; v < images.depth.rows; ++v)
    {
        const float* d = images.depth.ptr<float>(v);
        const auto* m = images.dynamicMask.empty() ? nullptr : images.dynamicMask.ptr<uint8_t>(v);
        auto* z = nearest.ptr<float>(v / kCell);
        auto* n = observed.ptr<int>(v / kCell);
        for (int u = 0; u < images.depth.cols; ++u)
        {
            if (!(d[u] >= lo && d[u] <= hi) || (m != nullptr && m[u] != 0))
                continue;
            float& cell = z[u / kCell];
            cell = n[u / kCell]++ == 0 ? d[u] : std::min(cell, d[u]);
        }
    }
    for (int r = 0; r < rows; ++r)
    {
        const int h = std::min(kCell, images.depth.rows - r * kCell);
        for (int c = 0; c < cols; ++c)
        {
            const int w = std::min(kCell, images.depth.cols - c * kCell);
            if (observed.at<int>(r, c) < kObserved * h * w)
                nearest.at<float>(r, c) = 0.0F;
        }
    }
    return nearest;
}

LatestView::LatestView(const std::vector<KeyFrameContribution>& contributions, double margin,
                       bool majority)
    : margin_(static_cast<float>(margin)), majority_(majority)
{
    views_.reserve(contributions.size());
    for (size_t k = 0; k < contributions.size(); ++k)
    {
        const KeyFrameContribution& c = contributions[k];
        if (c.static_depth_cells.empty() || !c.camera.isValid())
            continue;
        const Eigen::Matrix4d T_world_cam =
            c.T_world_cam.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
        views_.push_back({k, Eigen::Isometry3f(T_world_cam.inverse().cast<float>()), c.camera,
                          c.static_depth_cells});
    }
}

LatestView::Verdict LatestView::look(const View& view, const Eigen::Vector3f& p_world) const
{
    const Eigen::Vector3f q = view.T_cam_world * p_world;
    if (!(q.z() > 0.0F))
        return Verdict::NoView;
    // The pixel of the images the cells came from: the camera's distortion applied.
    const core::PinholeCamera& cam = view.camera;
    double x = q.x() / q.z(), y = q.y() / q.z();
    cam.distortNormalised(x, y);
    const auto cu = static_cast<int>(std::floor((cam.fx * x + cam.cx + 0.5) / kCell));
    const auto cv = static_cast<int>(std::floor((cam.fy * y + cam.cy + 0.5) / kCell));
    if (cu < 0 || cv < 0 || cu >= view.cells.cols || cv >= view.cells.rows)
        return Verdict::NoView;
    const float z = view.cells.at<float>(cv, cu);
    if (z == 0.0F)
        return Verdict::NoView;
    if (z < q.z() - margin_)
        return Verdict::Hidden;
    return z > q.z() + margin_ ? Verdict::Through : Verdict::Seen;
}

bool LatestView::seenThrough(const Eigen::Vector3f& p_world, size_t own) const
{
    Verdict newest = Verdict::NoView;
    int throughAfter = 0, seenAfter = 0;  // votes of the keyframes after p's own
    for (auto it = views_.rbegin(); it != views_.rend(); ++it)
    {
        const bool after = it->contribution > own;
        if (newest != Verdict::NoView && !(majority_ && after))
            break;  // the newest verdict found, and no more votes to count
        const Verdict v = look(*it, p_world);
        if (v != Verdict::Seen && v != Verdict::Through)
            continue;
        if (newest == Verdict::NoView)
            newest = v;
        if (after)
            (v == Verdict::Through ? throughAfter : seenAfter)++;
    }
    return newest == Verdict::Through ||
           (majority_ && throughAfter > 0 && throughAfter >= seenAfter);
}
}  // namespace smap::mapping
