// Top view of ground truth, aligned estimate and the error between them (like Figure 5 of the
// paper), rendered to an image with OpenCV.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>

#include "smap/eval/AbsoluteTrajectoryError.h"

namespace smap::eval
{
struct PlotOptions
{
    int width = 1100;
    int height = 850;
    std::string title = "Absolute trajectory error";
    /// Axes drawn horizontally and vertically (0 = x, 1 = y, 2 = z); -1 picks the two along
    /// which the ground truth varies most (a top view for any world convention).
    int horizontalAxis = -1;
    int verticalAxis = -1;
};

/// Returns a CV_8UC3 image (BGR).
cv::Mat renderAtePlot(const AteResult& ate, const PlotOptions& options = {});
/// Renders and writes a PNG atomically; throws std::runtime_error when it cannot be written.
void saveAtePlot(const std::string& path, const AteResult& ate, const PlotOptions& options = {});
}  // namespace smap::eval
