#include "smap/dynamic/DynamicFilter.h"

#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "smap/dynamic/FrameWarp.h"

namespace smap::dynamic
{
std::vector<float> DynamicResult::weights() const
{
    std::vector<float> w(keypoints.size(), 1.0F);
    for (size_t i = 0; i < keypoints.size(); ++i)
        if (keypoints[i].dynamic)
            w[i] = 0.0F;
    return w;
}

size_t DynamicResult::numDynamic() const
{
    size_t n = 0;
    for (const auto& k : keypoints)
        n += k.dynamic ? 1 : 0;
    return n;
}

DynamicFilter::DynamicFilter(const DynamicParameters& params) : params_(params) {}

DynamicResult DynamicFilter::process(const cv::Mat& colour, const cv::Mat& depth,
                                     const features::FeatureSet& features,
                                     const core::PinholeCamera& camera)
{
    const auto t0 = std::chrono::steady_clock::now();
    DynamicResult result;
    result.keypoints.resize(features.size());
    result.tau = params_.tau;
    cv::Mat grey;
    if (colour.channels() == 3)
        cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
    else
        grey = colour.clone();

    if (params_.mode != FilterMode::Off && !previousGrey_.empty() && features.size() > 0)
    {
        auto lap = std::chrono::steady_clock::now();
        auto msSinceLap = [&lap]()
        {
            const auto now = std::chrono::steady_clock::now();
            const double ms = std::chrono::duration<double, std::milli>(now - lap).count();
            lap = now;
            return ms;
        };
        result.egoMotion = estimateEgoMotionFivePoint(previousFeatures_, features, camera, params_);
        result.egoMotionMilliseconds = msSinceLap();
        if (result.egoMotion.valid)
        {
            const WarpedFrame warped = warpIntoCurrentView(previousGrey_, previousDepth_, camera,
                                                           result.egoMotion.T_cur_prev);
            result.warpMilliseconds = msSinceLap();
            // Flow from the warped previous frame to the current one, started at the current
            // keypoints (distorted pixels: both images are on the distorted grid).
            std::vector<cv::Point2f> from, to;
            for (const auto& kp : features.keypoints)
                from.push_back(kp.pt);
            std::vector<uint8_t> status;
            std::vector<float> err;
            cv::calcOpticalFlowPyrLK(
                warped.grey, grey, from, to, status, err,
                cv::Size(params_.lk_window, params_.lk_window), params_.lk_levels,
                cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01));
            result.flowMilliseconds = msSinceLap();
            for (size_t i = 0; i < from.size(); ++i)
            {
                if (status[i] == 0)
                    continue;
                const cv::Point2f d = to[i] - from[i];
                auto& e = result.keypoints[i];
                e.residual = std::sqrt(d.x * d.x + d.y * d.y);
                e.dynamic = e.residual > params_.tau;
            }
        }
    }
    previousGrey_ = grey;
    previousDepth_ = depth.clone();
    previousFeatures_ = features;
    result.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
}
}  // namespace smap::dynamic
