#include "StrongMode.h"

#include <algorithm>
#include <cmath>
#include <opencv2/video/tracking.hpp>

#include "StrongModeSteps.h"

namespace smap::dynamic
{
void StrongMode::buildPyramid(const cv::Mat& grey)
{
    cv::buildOpticalFlowPyramid(grey, currentPyramid_,
                                cv::Size(params_.strong_lk_window, params_.strong_lk_window),
                                params_.strong_lk_levels, true);
}

void StrongMode::remember(const DynamicResult& result, PastFrame& past)
{
    if (result.framesBack > 0 && result.egoMotion.valid)
    {
        lastMotion_ = result.egoMotion.T_cur_prev;
        lastFramesBack_ = result.framesBack;
    }
    else
    {
        lastMotion_.reset();
    }
    past.pyramid = std::move(currentPyramid_);
    currentPyramid_.clear();
    if (!result.evaluated)
        return;
    past.dynamic.resize(result.keypoints.size());
    for (size_t i = 0; i < result.keypoints.size(); ++i)
        past.dynamic[i] = result.keypoints[i].dynamic;
    past.cells =
        DecisionCells::count(past.features, past.dynamic, past.depth.cols, past.depth.rows);
}

EgoMotion StrongMode::estimateEgoMotion(const features::FeatureSet& features,
                                        const core::PinholeCamera& camera,
                                        const FrameHistory& history) const
{
    // No final iterative refinement: the flow tracks refine the pose later. The prior competing
    // with RANSAC is the last ego-motion over the same gap or, on the first comparison of a
    // sequence, a camera at rest: without it the first frames have no defence against people
    // who outvote the background (RANSAC then locks onto them, and the next frames' priors
    // with it).
    std::optional<Eigen::Isometry3d> prior;
    if (lastMotion_ && lastFramesBack_ == history.size())
        prior = lastMotion_;
    else if (!lastMotion_ && history.size() == 1)
        prior = Eigen::Isometry3d::Identity();
    EgoMotion ego = estimateEgoMotionDepthPnp(history.front().features, features, camera, params_,
                                              false, history.front().dynamic, prior);
    if (ego.valid)
        return ego;
    return estimateEgoMotionFivePoint(history.front().features, features, camera, params_);
}

void StrongMode::evaluate(const cv::Mat& depth, const features::FeatureSet& features,
                          const core::PinholeCamera& camera, const FrameHistory& history,
                          const Stopwatch& lap, DynamicResult& result) const
{
    const PastFrame& reference = history.front();
    result.egoMotion = estimateEgoMotion(features, camera, history);
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
        currentPyramid_, reference.pyramid, features, prediction.pixels, params_);
    result.flow_ms = lap();
    const std::vector<bool> wasDynamic =
        dynamicBefore(reference, tracks.status, tracks.tracked, prediction.pixels);
    for (size_t i = 0; i < wasDynamic.size(); ++i)
    {
        result.keypoints[i].wasDynamic = wasDynamic[i];
        if (tracks.status[i] != 0)
            result.keypoints[i].inReference = tracks.tracked[i];
    }
    strong::refineEgoMotionOnTracks(hypotheses, tracks,
                                    strong::refinementCandidates(hypotheses, tracks, wasDynamic),
                                    camera, params_, result.egoMotion.T_cur_prev, prediction);
    strong::measureEvidence(features, hypotheses, prediction, tracks, reference.depth, camera,
                            result.egoMotion.T_cur_prev, params_, result.keypoints);
    decide(features, result);
}

std::vector<bool> StrongMode::dynamicBefore(const PastFrame& reference,
                                            const std::vector<uint8_t>& status,
                                            const std::vector<cv::Point2f>& tracked,
                                            const std::vector<cv::Point2f>& predicted)
{
    std::vector<bool> out(tracked.size(), false);
    const DecisionCells& cells = reference.cells;
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

cv::Mat StrongMode::moverRegions(const FrameHistory& history) const
{
    if (history.empty())
        return {};
    const PastFrame& last = history.back();
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

void StrongMode::decide(const features::FeatureSet& features, DynamicResult& result) const
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
