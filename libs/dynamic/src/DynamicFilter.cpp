#include "smap/dynamic/DynamicFilter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "smap/dynamic/FrameWarp.h"
#include "smap/features/FeatureGrid.h"

namespace smap::dynamic
{
std::vector<float> DynamicResult::weights() const
{
    std::vector<float> w(keypoints.size(), evaluated ? 1.0F : 0.0F);
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

    result.evaluated = params_.mode == FilterMode::Off || !previousGrey_.empty();
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
        const bool strong = params_.mode == FilterMode::Strong;
        if (strong)
            result.egoMotion =
                estimateEgoMotionDepthPnp(previousFeatures_, features, camera, params_);
        if (!result.egoMotion.valid)
            result.egoMotion =
                estimateEgoMotionFivePoint(previousFeatures_, features, camera, params_);
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
                e.flow = e.residual > params_.tau;
                e.dynamic = e.flow;
            }
            if (strong)
                decideStrong(features, warped.depth, result);
        }
    }
    previousGrey_ = grey;
    previousDepth_ = depth.clone();
    previousFeatures_ = features;
    result.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
}
void DynamicFilter::decideStrong(const features::FeatureSet& features, const cv::Mat& warped_depth,
                                 DynamicResult& result) const
{
    auto& kps = result.keypoints;
    // Adaptive tau from the frame's residual statistics: most keypoints are static, so the
    // median and MAD describe how well the ego-motion compensates this frame.
    std::vector<float> r;
    for (const auto& e : kps)
        if (e.residual >= 0.0F)
            r.push_back(e.residual);
    if (r.size() < 10)
        return;
    auto median = [](std::vector<float> v)
    {
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return static_cast<double>(v[v.size() / 2]);
    };
    const double med = median(r);
    std::vector<float> dev;
    dev.reserve(r.size());
    for (float x : r)
        dev.push_back(std::abs(x - static_cast<float>(med)));
    const double sigma = 1.4826 * median(dev);
    result.tau = std::clamp(med + params_.tau_sigmas * sigma, params_.tau_min, params_.tau);

    for (size_t i = 0; i < kps.size(); ++i)
    {
        auto& e = kps[i];
        e.flow = e.residual >= 0.0F && e.residual > result.tau;
        // Depth: something now in front of the surface the previous frame saw there.
        const float zm = features.depth.empty() ? 0.0F : features.depth[i];
        const cv::Point2f& p = features.keypoints[i].pt;
        const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
        if (zm > 0.0F && u >= 0 && v >= 0 && u < warped_depth.cols && v < warped_depth.rows)
        {
            const float zw = warped_depth.at<float>(v, u);
            const double margin = std::max(params_.depth_margin, params_.depth_ratio * zw);
            e.depth = zw > 0.0F && zm < zw - margin;
        }
        e.dynamic = e.flow || e.depth;
    }
    // Region growing over depth-connected neighbours (two Jacobi sweeps, deterministic).
    if (params_.region_radius <= 0.0)
        return;
    std::vector<int> levels(features.size(), 0);
    int maxX = 1, maxY = 1;
    for (const auto& kp : features.keypoints)
    {
        maxX = std::max(maxX, static_cast<int>(kp.pt.x) + 1);
        maxY = std::max(maxY, static_cast<int>(kp.pt.y) + 1);
    }
    std::vector<cv::Point2f> pts;
    for (const auto& kp : features.keypoints)
        pts.push_back(kp.pt);
    const features::FeatureGrid grid(pts, levels, maxX, maxY, 32);
    for (int sweep = 0; sweep < 2; ++sweep)
    {
        std::vector<bool> was(kps.size());
        for (size_t i = 0; i < kps.size(); ++i)
            was[i] = kps[i].dynamic;
        for (size_t i = 0; i < kps.size(); ++i)
        {
            const float zi = features.depth.empty() ? 0.0F : features.depth[i];
            if (was[i] || zi <= 0.0F)
                continue;
            int near = 0, dyn = 0;
            for (size_t j :
                 grid.query(pts[i].x, pts[i].y, static_cast<float>(params_.region_radius)))
            {
                if (j == i || features.depth[j] <= 0.0F ||
                    std::abs(features.depth[j] - zi) > params_.region_depth)
                    continue;
                near++;
                dyn += was[j] ? 1 : 0;
            }
            if (near >= params_.region_min_neighbours && 2 * dyn > near)
            {
                kps[i].region = true;
                kps[i].dynamic = true;
            }
        }
    }
}
}  // namespace smap::dynamic
