#include "PaperMode.h"

#include <cmath>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "smap/dynamic/FrameWarp.h"

namespace smap::dynamic
{
void PaperMode::evaluate(const cv::Mat& grey, const features::FeatureSet& features,
                         const core::PinholeCamera& camera, const PastFrame& previous,
                         const Stopwatch& lap, DynamicResult& result) const
{
    result.egoMotion = estimateEgoMotionFivePoint(previous.features, features, camera, params_);
    result.ego_motion_ms = lap();
    if (!result.egoMotion.valid)
        return;
    const WarpedFrame warped =
        warpIntoCurrentView(previous.grey, previous.depth, camera, result.egoMotion.T_cur_prev);
    result.warp_ms = lap();
    // Flow from the warped previous frame to the current one, started at the current
    // keypoints (distorted pixels: both images are on the distorted grid).
    std::vector<cv::Point2f> from, to;
    for (const auto& kp : features.keypoints)
        from.push_back(kp.pt);
    std::vector<uint8_t> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(
        warped.grey, grey, from, to, status, err, cv::Size(params_.lk_window, params_.lk_window),
        params_.lk_levels,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01));
    result.flow_ms = lap();
    for (size_t i = 0; i < from.size(); ++i)
    {
        if (status[i] == 0)
            continue;
        const cv::Point2f d = to[i] - from[i];
        auto& e = result.keypoints[i];
        e.residual = std::sqrt(d.x * d.x + d.y * d.y);
        e.flow = e.residual > params_.tau;
        e.dynamic = e.flow;
    }
}
}  // namespace smap::dynamic
