#include "smap/slam/LoopCloser.h"

#include <chrono>
#include <cmath>

#include "KeyFrameQueue.h"
#include "LoopDetector.h"
#include "smap/core/Elapsed.h"
#include "smap/slam/BundleAdjustment.h"
#include "smap/slam/LocalMapper.h"
#include "smap/slam/LoopCorrection.h"
#include "smap/slam/Map.h"

namespace smap::slam
{
using core::secondsSince;

LoopCloser::LoopCloser(Map& map, LocalMapper& mapper, const LoopClosingParameters& params,
                       const LocalMappingParameters& mapping)
    : COutputLogger("loop-closing"),
      map_(map),
      mapper_(mapper),
      params_(params),
      covisibilityMinWeight_(mapping.covisibility_min_weight),
      baMinSharedObservations_(mapping.ba_min_shared_observations),
      detector_(std::make_unique<LoopDetector>(params)),
      queue_(std::make_unique<KeyFrameQueue>(params_.enabled && params_.threaded,
                                             [this](const std::shared_ptr<KeyFrame>& kf)
                                             { process(kf); }))
{
}

LoopCloser::~LoopCloser()
{
    stop();
}

void LoopCloser::stop()
{
    queue_->stop();
}

void LoopCloser::insertKeyFrame(const std::shared_ptr<KeyFrame>& kf)
{
    if (params_.enabled)
        queue_->push(kf);
}

void LoopCloser::waitUntilIdle()
{
    queue_->waitUntilIdle();
}

LoopClosingStats LoopCloser::stats() const
{
    std::lock_guard<std::mutex> lock(statsMutex_);
    return stats_;
}

void LoopCloser::process(const std::shared_ptr<KeyFrame>& kf)
{
    const auto t0 = std::chrono::steady_clock::now();
    const LoopDetector::Outcome found = detector_->detect(kf, map_);
    for (const auto& c : found.checks)
    {
        MRPT_LOG_DEBUG_FMT(
            "keyframe %lu (frame %lu): candidate %lu scored %d, %d descriptor "
            "matches, %d inliers, %d projected",
            static_cast<unsigned long>(kf->id()), static_cast<unsigned long>(kf->frameId()),
            static_cast<unsigned long>(c.candidateId), c.score, c.descriptorMatches, c.inliers,
            c.projectedMatches);
    }
    {
        std::lock_guard<std::mutex> lock(statsMutex_);
        stats_.keyframesChecked++;
        stats_.candidatesVerified += found.checks.size();
        stats_.candidatesRejected += found.checks.size() - (found.match ? 1 : 0);
    }
    if (!found.match)
        return;
    const LoopMatch& match = *found.match;
    LoopClosure c;
    c.keyFrameId = kf->id();
    c.loopKeyFrameId = match.loop->id();
    c.frameId = kf->frameId();
    c.loopFrameId = match.loop->frameId();
    c.timestamp = kf->timestamp();
    c.loopTimestamp = match.loop->timestamp();
    c.inliers = match.inliers;
    c.projectedMatches = match.projectedMatches;
    close(kf, match, c);
    c.correctionSeconds = secondsSince(t0) - c.globalBaSeconds;
    if (!c.corrected)
    {
        MRPT_LOG_DEBUG_FMT(
            "consistent revisit: keyframe %lu revisits keyframe %lu (%.3f m, %.2f deg)",
            static_cast<unsigned long>(c.keyFrameId), static_cast<unsigned long>(c.loopKeyFrameId),
            c.correction_m, c.correction_deg);
        std::lock_guard<std::mutex> lock(statsMutex_);
        stats_.closures.push_back(c);
        return;
    }
    MRPT_LOG_INFO_FMT(
        "loop closed: keyframe %lu (frame %lu) revisits keyframe %lu (frame %lu), %d inliers, "
        "%d projected; %.3f m %.2f deg off, %d keyframes, %d points fused, %.1f ms + BA %.1f ms",
        static_cast<unsigned long>(c.keyFrameId), static_cast<unsigned long>(c.frameId),
        static_cast<unsigned long>(c.loopKeyFrameId), static_cast<unsigned long>(c.loopFrameId),
        c.inliers, c.projectedMatches, c.correction_m, c.correction_deg, c.keyframesCorrected,
        c.pointsFused, 1e3 * c.correctionSeconds, 1e3 * c.globalBaSeconds);
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_.closures.push_back(c);
}
void LoopCloser::close(const std::shared_ptr<KeyFrame>& kf, const LoopMatch& match, LoopClosure& c)
{
    std::lock_guard<std::mutex> still(mapper_.processingMutex());
    {
        std::lock_guard<std::mutex> lock(map_.mutex());
        const Eigen::Isometry3d T = kf->T_cam_world(), diff = T.inverse() * match.T_cam_world;
        c.correction_m =
            (T.inverse().translation() - match.T_cam_world.inverse().translation()).norm();
        c.correction_deg = Eigen::AngleAxisd(diff.rotation()).angle() * 180.0 / M_PI;
        c.T_loop_keyframe = match.loop->T_cam_world() * match.T_cam_world.inverse();
    }
    c.corrected = c.correction_m >= params_.min_correction_m ||
                  c.correction_deg >= params_.min_correction_deg;
    if (!c.corrected)
    {
        c.pointsFused = joinConsistentRevisit(map_, kf, match, loopEdges_, covisibilityMinWeight_);
        return;
    }
    const auto outcome = correctLoop(map_, kf, match, loopEdges_, params_.pose_graph_iterations,
                                     covisibilityMinWeight_);
    c.keyframesCorrected = outcome.keyframes;
    c.pointsFused = outcome.pointsFused;
    if (params_.global_ba_iterations > 0)
    {
        const auto tBa = std::chrono::steady_clock::now();
        globalBundleAdjustment(map_, params_.global_ba_iterations, baMinSharedObservations_,
                               mapper_.keyFrameWaiting());
        c.globalBaSeconds = secondsSince(tBa);
    }
}
}  // namespace smap::slam
