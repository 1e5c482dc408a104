#include "smap/features/FeatureGrid.h"

#include <utility>

namespace smap::features
{
FeatureGrid::FeatureGrid(std::vector<cv::Point2f> points, std::vector<int> levels, int width,
                         int height, int cell)
    : cols_(std::max(1, (width + cell - 1) / cell)),
      rows_(std::max(1, (height + cell - 1) / cell)),
      invCell_(1.0F / static_cast<float>(cell)),
      points_(std::move(points)),
      levels_(std::move(levels))
{
    const size_t numCells = static_cast<size_t>(cols_) * static_cast<size_t>(rows_);
    std::vector<size_t> cellOf(points_.size());
    cellStart_.assign(numCells + 1, 0);
    for (size_t i = 0; i < points_.size(); ++i)
    {
        const int cx = std::clamp(static_cast<int>(points_[i].x * invCell_), 0, cols_ - 1);
        const int cy = std::clamp(static_cast<int>(points_[i].y * invCell_), 0, rows_ - 1);
        cellOf[i] = static_cast<size_t>(cy) * static_cast<size_t>(cols_) + static_cast<size_t>(cx);
        cellStart_[cellOf[i] + 1]++;
    }
    for (size_t c = 0; c < numCells; ++c)
        cellStart_[c + 1] += cellStart_[c];
    // Counting sort: within a cell, increasing index order.
    items_.resize(points_.size());
    std::vector<size_t> next(cellStart_.begin(), cellStart_.end() - 1);
    for (size_t i = 0; i < points_.size(); ++i)
        items_[next[cellOf[i]]++] = i;
}

std::vector<size_t> FeatureGrid::query(float u, float v, float radius, int min_level,
                                       int max_level) const
{
    std::vector<size_t> out;
    forEachNear(u, v, radius, min_level, max_level, [&out](size_t i) { out.push_back(i); });
    return out;
}
}  // namespace smap::features
