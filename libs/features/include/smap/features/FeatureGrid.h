// A uniform grid over the image that finds the keypoints near a predicted position quickly, for
// projection search.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <opencv2/core/types.hpp>
#include <vector>

namespace smap::features
{
class FeatureGrid
{
public:
    FeatureGrid() = default;
    /// Bins `points` (undistorted pixels, with their pyramid `levels`) of an image of
    /// width x height into cells of about `cell` pixels; points outside go to border cells.
    FeatureGrid(std::vector<cv::Point2f> points, std::vector<int> levels, int width, int height,
                int cell = 16);

    /// Indices of points within `radius` (square window) of (u, v) whose level is in
    /// [min_level, max_level] (a negative bound is open), in increasing index order per cell.
    std::vector<size_t> query(float u, float v, float radius, int min_level = -1,
                              int max_level = -1) const;

    /// Calls `visit(index)` for each point `query` would return, in the same order, without
    /// allocating.
    template <typename Visit>
    void forEachNear(float u, float v, float radius, int min_level, int max_level,
                     Visit&& visit) const
    {
        if (cellStart_.empty())
            return;
        const int x0 = std::max(0, static_cast<int>(std::floor((u - radius) * invCell_)));
        const int x1 = std::min(cols_ - 1, static_cast<int>(std::floor((u + radius) * invCell_)));
        const int y0 = std::max(0, static_cast<int>(std::floor((v - radius) * invCell_)));
        const int y1 = std::min(rows_ - 1, static_cast<int>(std::floor((v + radius) * invCell_)));
        for (int cy = y0; cy <= y1; ++cy)
        {
            const size_t row = static_cast<size_t>(cy) * static_cast<size_t>(cols_);
            // The cells x0..x1 of a row are contiguous in the flat index array.
            const size_t begin = cellStart_[row + static_cast<size_t>(x0)];
            const size_t end = cellStart_[row + static_cast<size_t>(x1) + 1];
            for (size_t k = begin; k < end; ++k)
            {
                const size_t i = items_[k];
                const cv::Point2f& p = points_[i];
                if (std::abs(p.x - u) > radius || std::abs(p.y - v) > radius)
                    continue;
                const int l = levels_[i];
                if ((min_level >= 0 && l < min_level) || (max_level >= 0 && l > max_level))
                    continue;
                visit(i);
            }
        }
    }

private:
    int cols_ = 0, rows_ = 0;
    float invCell_ = 1.0F;
    /// Cell c holds items_[cellStart_[c] .. cellStart_[c + 1]), row-major cells.
    std::vector<size_t> cellStart_;
    std::vector<size_t> items_;
    std::vector<cv::Point2f> points_;
    std::vector<int> levels_;
};
}  // namespace smap::features
