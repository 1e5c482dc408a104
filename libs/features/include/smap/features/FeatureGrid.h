// A uniform grid over the image that finds the keypoints near a predicted position quickly, for
// projection search.
#pragma once

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

private:
    int cols_ = 0, rows_ = 0;
    float invCell_ = 1.0F;
    std::vector<std::vector<size_t>> cells_;
    std::vector<cv::Point2f> points_;
    std::vector<int> levels_;
};
}  // namespace smap::features
