// The dynamic filter as the paper describes it (docs/method.md section 2): five-point ego-motion,
// the previous frame warped into the current view, Lucas-Kanade flow, tau. Private to
// libs/dynamic.
#pragma once

#include "FrameHistory.h"
#include "smap/core/PinholeCamera.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/dynamic/DynamicParameters.h"

namespace smap::dynamic
{
class PaperMode
{
public:
    explicit PaperMode(const DynamicParameters& params) : params_(params) {}

    /// The residual flow and decision of every keypoint of the current frame (grey) against
    /// the previous one.
    void evaluate(const cv::Mat& grey, const features::FeatureSet& features,
                  const core::PinholeCamera& camera, const PastFrame& previous,
                  const Stopwatch& lap, DynamicResult& result) const;

private:
    DynamicParameters params_;
};
}  // namespace smap::dynamic
