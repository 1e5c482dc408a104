#include "smap/dynamic/DynamicFilter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "StrongModeSteps.h"
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

std::vector<bool> DynamicResult::mappable() const
{
    const bool measured = std::any_of(keypoints.begin(), keypoints.end(),
                                      [](const KeypointEvidence& k) { return k.residual >= 0.0F; });
    if (!measured)
        return {};
    std::vector<bool> m(keypoints.size());
    for (size_t i = 0; i < keypoints.size(); ++i)
        m[i] = !keypoints[i].dynamic && keypoints[i].residual >= 0.0F;
    return m;
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

    auto lap = std::chrono::steady_clock::now();
    const Stopwatch msSinceLap = [&lap]()
    {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - lap).count();
        lap = now;
        return ms;
    };
    const bool strong = params_.mode == FilterMode::Strong;
    if (strong)
    {
        // The current pyramid is also the next frame's previous one.
        cv::buildOpticalFlowPyramid(grey, currentPyramid_,
                                    cv::Size(params_.strong_lk_window, params_.strong_lk_window),
                                    params_.strong_lk_levels, true);
        result.warp_ms = msSinceLap();
    }
    result.evaluated = params_.mode == FilterMode::Off || !history_.empty();
    if (params_.mode != FilterMode::Off && !history_.empty() && features.size() > 0)
    {
        result.framesBack = history_.size();
        if (strong)
            processStrong(depth, features, camera, msSinceLap, result);
        else
            processPaper(grey, features, camera, msSinceLap, result);
    }
    if (strong && result.framesBack > 0 && result.egoMotion.valid)
    {
        lastMotion_ = result.egoMotion.T_cur_prev;
        lastFramesBack_ = result.framesBack;
    }
    else
    {
        lastMotion_.reset();
    }
    if (params_.mode != FilterMode::Off)
    {
        PastFrame past;
        past.grey = grey;
        past.pyramid = std::move(currentPyramid_);
        currentPyramid_.clear();
        past.depth = depth;
        past.features = features;
        if (result.evaluated && strong)
        {
            past.dynamic.resize(result.keypoints.size());
            for (size_t i = 0; i < result.keypoints.size(); ++i)
                past.dynamic[i] = result.keypoints[i].dynamic;
            past.cells = DecisionCells::count(features, past.dynamic, depth.cols, depth.rows);
        }
        history_.push_back(std::move(past));
        const size_t keep = strong ? static_cast<size_t>(params_.frame_gap) : 1;
        while (history_.size() > keep)
            history_.pop_front();
    }
    result.total_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
}
void DynamicFilter::processPaper(const cv::Mat& grey, const features::FeatureSet& features,
                                 const core::PinholeCamera& camera, const Stopwatch& lap,
                                 DynamicResult& result) const
{
    result.egoMotion = estimateEgoMotionFivePoint(reference().features, features, camera, params_);
    result.ego_motion_ms = lap();
    if (!result.egoMotion.valid)
        return;
    const WarpedFrame warped = warpIntoCurrentView(reference().grey, reference().depth, camera,
                                                   result.egoMotion.T_cur_prev);
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

EgoMotion DynamicFilter::estimateStrongEgoMotion(const features::FeatureSet& features,
                                                 const core::PinholeCamera& camera) const
{
    // No final iterative refinement: the flow tracks refine the pose later. The prior competing
    // with RANSAC is the last ego-motion over the same gap or, on the first comparison of a
    // sequence, a camera at rest: without it the first frames have no defence against people
    // who outvote the background (RANSAC then locks onto them, and the next frames' priors
    // with it).
    std::optional<Eigen::Isometry3d> prior;
    if (lastMotion_ && lastFramesBack_ == history_.size())
        prior = lastMotion_;
    else if (!lastMotion_ && history_.size() == 1)
        prior = Eigen::Isometry3d::Identity();
    EgoMotion ego = estimateEgoMotionDepthPnp(reference().features, features, camera, params_,
                                              false, reference().dynamic, prior);
    if (ego.valid)
        return ego;
    return estimateEgoMotionFivePoint(reference().features, features, camera, params_);
}

void DynamicFilter::processStrong(const cv::Mat& depth, const features::FeatureSet& features,
                                  const core::PinholeCamera& camera, const Stopwatch& lap,
                                  DynamicResult& result) const
{
    result.egoMotion = estimateStrongEgoMotion(features, camera);
    result.ego_motion_ms = lap();
    if (!result.egoMotion.valid)
        return;
    // Instead of warping the whole previous image, predict where each current keypoint was in
    // the reference frame (its depth and the ego-motion), then let Lucas-Kanade find where it
    // really was, starting from the prediction: a static point is found at the prediction, a
    // mover away from it. Same residual as the warp's, at a fraction of the cost.
    const strong::DepthHypotheses hypotheses = strong::hypothesiseDepths(features, depth, camera);
    strong::Prediction prediction =
        strong::predictInReference(hypotheses, camera, result.egoMotion.T_cur_prev);
    const strong::FlowTracks tracks = strong::trackIntoReference(
        currentPyramid_, reference().pyramid, features, prediction.pixels, params_);
    result.flow_ms = lap();
    const std::vector<bool> wasDynamic =
        dynamicBefore(tracks.status, tracks.tracked, prediction.pixels);
    for (size_t i = 0; i < wasDynamic.size(); ++i)
        result.keypoints[i].wasDynamic = wasDynamic[i];
    strong::refineEgoMotionOnTracks(hypotheses, tracks,
                                    strong::refinementCandidates(hypotheses, tracks, wasDynamic),
                                    camera, params_, result.egoMotion.T_cur_prev, prediction);
    strong::measureEvidence(features, hypotheses, prediction, tracks, reference().depth, camera,
                            result.egoMotion.T_cur_prev, params_, result.keypoints);
    decideStrong(features, result);
}

std::vector<bool> DynamicFilter::dynamicBefore(const std::vector<uint8_t>& status,
                                               const std::vector<cv::Point2f>& tracked,
                                               const std::vector<cv::Point2f>& predicted) const
{
    std::vector<bool> out(tracked.size(), false);
    const DecisionCells& cells = reference().cells;
    if (cells.all.empty())
        return out;
    for (size_t i = 0; i < tracked.size(); ++i)
    {
        const cv::Point2f& q = status[i] != 0 ? tracked[i] : predicted[i];
        const int cx = static_cast<int>(std::floor(q.x / DecisionCells::kCell));
        const int cy = static_cast<int>(std::floor(q.y / DecisionCells::kCell));
        const auto [all, dyn] = cells.around(cx, cy, 1);
        out[i] = 2 * dyn > all;
    }
    return out;
}

cv::Mat DynamicFilter::moverRegions() const
{
    if (params_.mode != FilterMode::Strong || history_.empty())
        return {};
    const PastFrame& last = history_.back();
    const DecisionCells& c = last.cells;
    if (c.all.empty() || last.dynamic.empty())
        return {};
    const auto dynamicKeypoints = std::count(last.dynamic.begin(), last.dynamic.end(), true);
    if (static_cast<double>(dynamicKeypoints) <=
        params_.extraction_priority_above * static_cast<double>(last.dynamic.size()))
        return {};
    // 5 x 5 cells (40 px): a 3 x 3 block holds about two keypoints, too few to cover a person.
    constexpr int kRadius = 2;
    cv::Mat mask(c.rows, c.cols, CV_8UC1, cv::Scalar(0));
    bool any = false;
    for (int y = 0; y < c.rows; ++y)
    {
        for (int x = 0; x < c.cols; ++x)
        {
            const auto [all, dynamic] = c.around(x, y, kRadius);
            if (dynamic >= 2 && 2 * dynamic > all)
            {
                mask.at<uint8_t>(y, x) = 255;
                any = true;
            }
        }
    }
    return any ? mask : cv::Mat();
}

std::pair<int, int> DynamicFilter::DecisionCells::around(int cx, int cy, int radius) const
{
    int n = 0, nDynamic = 0;
    for (int y = std::max(0, cy - radius); y <= std::min(rows - 1, cy + radius); ++y)
    {
        for (int x = std::max(0, cx - radius); x <= std::min(cols - 1, cx + radius); ++x)
        {
            const size_t k =
                static_cast<size_t>(y) * static_cast<size_t>(cols) + static_cast<size_t>(x);
            n += all[k];
            nDynamic += dynamic[k];
        }
    }
    return {n, nDynamic};
}

DynamicFilter::DecisionCells DynamicFilter::DecisionCells::count(
    const features::FeatureSet& features, const std::vector<bool>& dynamic, int width, int height)
{
    DecisionCells c;
    c.cols = (width + kCell - 1) / kCell;
    c.rows = (height + kCell - 1) / kCell;
    c.all.assign(static_cast<size_t>(c.cols) * static_cast<size_t>(c.rows), 0);
    c.dynamic.assign(c.all.size(), 0);
    for (size_t i = 0; i < features.size() && i < dynamic.size(); ++i)
    {
        const int x =
            std::clamp(static_cast<int>(features.keypoints[i].pt.x) / kCell, 0, c.cols - 1);
        const int y =
            std::clamp(static_cast<int>(features.keypoints[i].pt.y) / kCell, 0, c.rows - 1);
        const auto k =
            static_cast<size_t>(y) * static_cast<size_t>(c.cols) + static_cast<size_t>(x);
        c.all[k]++;
        c.dynamic[k] += dynamic[i] ? 1 : 0;
    }
    return c;
}

void DynamicFilter::decideStrong(const features::FeatureSet& features, DynamicResult& result) const
{
    auto& evidence = result.keypoints;
    const std::optional<double> tau = strong::adaptiveTau(evidence, params_);
    if (!tau)
    {
        for (auto& e : evidence)
            e.dynamic = e.depth;
        return;
    }
    result.tau = *tau;
    for (auto& e : evidence)
    {
        e.flow = e.residual >= 0.0F && e.residual > result.tau;
        e.dynamic = e.flow || e.depth;
    }
    if (params_.region_radius <= 0.0)
        return;
    const strong::NeighbourCounter neighbours(features, params_);
    if (params_.isolated_fraction > 0.0 && !features.depth.empty())
        strong::overruleIsolatedFlow(features, neighbours, params_, evidence);
    strong::growDynamicRegions(features, neighbours, params_, evidence);
}
}  // namespace smap::dynamic
