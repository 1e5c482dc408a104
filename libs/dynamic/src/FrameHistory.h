// The frames the dynamic filter compares a new frame with, shared by its modes (PaperMode,
// StrongMode). Private to libs/dynamic.
#pragma once

#include <deque>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <utility>
#include <vector>

#include "smap/features/FeatureSet.h"

namespace smap::dynamic
{
/// Milliseconds since its previous call (the stage timings of DynamicResult).
using Stopwatch = std::function<double()>;

/// A frame's decisions counted per 8 px cell: where a later frame's keypoint was, the 3 x 3
/// cells around it say whether it was among movers (temporal evidence).
struct DecisionCells
{
    static constexpr int kCell = 8;
    int cols = 0, rows = 0;
    std::vector<int> all, dynamic;  ///< keypoints and dynamic keypoints per cell, row-major

    static DecisionCells count(const features::FeatureSet& features,
                               const std::vector<bool>& dynamic, int width, int height);
    /// Keypoints and dynamic keypoints in the (2 radius + 1)^2 cells around cell (cx, cy),
    /// clipped to the grid.
    std::pair<int, int> around(int cx, int cy, int radius) const;
};

/// A frame kept for comparison with later ones.
struct PastFrame
{
    double timestamp = 0.0;  ///< s
    cv::Mat grey;
    std::vector<cv::Mat> pyramid;  ///< Lucas-Kanade pyramid with derivatives (strong)
    cv::Mat depth;
    features::FeatureSet features;
    /// Its keypoints' decisions (strong; empty when not evaluated): the ego-motion of a later
    /// frame leaves them out, so that people filling half the view do not pull it.
    std::vector<bool> dynamic;
    DecisionCells cells;  ///< `dynamic` per cell (empty with it)
};

/// Oldest first. The reference of a new frame is the front: the previous frame (paper), or
/// the newest frame at least frame_gap_s older (strong; the oldest kept at the start).
using FrameHistory = std::deque<PastFrame>;
}  // namespace smap::dynamic
