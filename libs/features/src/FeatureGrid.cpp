#include "smap/features/FeatureGrid.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace smap::features
{
FeatureGrid::FeatureGrid(std::vector<cv::Point2f> points, std::vector<int> levels, int width,
                         int height, int cell)
    : cols_(std::max(1, (width + cell - 1) / cell)),
      rows_(std::max(1, (height + cell - 1) / cell)),
      invCell_(1.0F / static_cast<float>(cell)),
      cells_(static_cast<size_t>(cols_) * static_cast<size_t>(rows_)),
      points_(std::move(points)),
      levels_(std::move(levels))
{
    for (size_t i = 0; i < points_.size(); ++i)
    {
        const int cx = std::clamp(static_cast<int>(points_[i].x * invCell_), 0, cols_ - 1);
        const int cy = std::clamp(static_cast<int>(points_[i].y * invCell_), 0, rows_ - 1);
        cells_[static_cast<size_t>(cy) * static_cast<size_t>(cols_) + static_cast<size_t>(cx)]
            .push_back(i);
    }
}

std::vector<size_t> FeatureGrid::query(float u, float v, float radius, int min_level,
                                       int max_level) const
{
    std::vector<size_t> out;
    if (cells_.empty())
        return out;
    const int x0 = std::max(0, static_cast<int>(std::floor((u - radius) * invCell_)));
    const int x1 = std::min(cols_ - 1, static_cast<int>(std::floor((u + radius) * invCell_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((v - radius) * invCell_)));
    const int y1 = std::min(rows_ - 1, static_cast<int>(std::floor((v + radius) * invCell_)));
    for (int cy = y0; cy <= y1; ++cy)
    {
        for (int cx = x0; cx <= x1; ++cx)
        {
            for (size_t i : cells_[static_cast<size_t>(cy) * static_cast<size_t>(cols_) +
                                   static_cast<size_t>(cx)])
            {
                const cv::Point2f& p = points_[i];
                if (std::abs(p.x - u) > radius || std::abs(p.y - v) > radius)
                    continue;
                const int l = levels_[i];
                if ((min_level >= 0 && l < min_level) || (max_level >= 0 && l > max_level))
                    continue;
                out.push_back(i);
            }
        }
    }
    return out;
}
}  // namespace smap::features
