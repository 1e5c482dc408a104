#include "smap/dynamic/DynamicFilter.h"

#include <algorithm>
#include <chrono>
#include <opencv2/imgproc.hpp>

#include "FrameHistory.h"
#include "PaperMode.h"
#include "StrongMode.h"
#include "smap/core/RecordingTime.h"

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

struct DynamicFilter::State
{
    FrameHistory history;
    PaperMode paper;
    StrongMode strong;
};

DynamicFilter::DynamicFilter(const DynamicParameters& params)
    : params_(params),
      state_(std::make_unique<State>(State{{}, PaperMode(params), StrongMode(params)}))
{
}

DynamicFilter::~DynamicFilter() = default;
DynamicFilter::DynamicFilter(DynamicFilter&&) noexcept = default;
DynamicFilter& DynamicFilter::operator=(DynamicFilter&&) noexcept = default;

void DynamicFilter::reset()
{
    state_->history.clear();
    state_->strong.reset();
}

cv::Mat DynamicFilter::moverRegions() const
{
    if (params_.mode != FilterMode::Strong)
        return {};
    return state_->strong.moverRegions(state_->history);
}

DynamicResult DynamicFilter::process(const cv::Mat& colour, const cv::Mat& depth,
                                     const features::FeatureSet& features,
                                     const core::PinholeCamera& camera, double timestamp)
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
    FrameHistory& history = state_->history;
    if (params_.mode == FilterMode::Strong)
        dropFramesBeforeGap(timestamp);
    result.evaluated = params_.mode == FilterMode::Off || !history.empty();
    const bool compare = params_.mode != FilterMode::Off && !history.empty() && features.size() > 0;
    if (compare)
        result.framesBack = history.size();
    switch (params_.mode)
    {
        case FilterMode::Off:
            break;
        case FilterMode::Paper:
            if (compare)
                state_->paper.evaluate(grey, features, camera, history.front(), msSinceLap, result);
            remember(grey, depth, features, result, 1, timestamp);
            break;
        case FilterMode::Strong:
            // The current pyramid is also the next frames' reference pyramid.
            state_->strong.buildPyramid(grey);
            result.warp_ms = msSinceLap();
            if (compare)
                state_->strong.evaluate(depth, features, camera, history, msSinceLap, result);
            remember(grey, depth, features, result, kMaxHistory, timestamp);
            break;
    }
    result.total_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

void DynamicFilter::dropFramesBeforeGap(double timestamp)
{
    FrameHistory& history = state_->history;
    while (history.size() >= 2 &&
           core::reached(timestamp - history[1].timestamp, params_.frame_gap_s))
        history.pop_front();
}

void DynamicFilter::remember(const cv::Mat& grey, const cv::Mat& depth,
                             const features::FeatureSet& features, const DynamicResult& result,
                             size_t keep, double timestamp)
{
    PastFrame past;
    past.timestamp = timestamp;
    past.grey = grey;
    past.depth = depth;
    past.features = features;
    if (params_.mode == FilterMode::Strong)
        state_->strong.remember(result, past);
    state_->history.push_back(std::move(past));
    while (state_->history.size() > keep)
        state_->history.pop_front();
}
}  // namespace smap::dynamic
