#include "smap/slam/Tracker.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "smap/core/Elapsed.h"
#include "smap/core/RecordingTime.h"
#include "smap/features/DescriptorMatcher.h"
#include "smap/features/RotationConsistency.h"
#include "smap/slam/LocalMapper.h"
#include "smap/slam/Map.h"
#include "smap/slam/PoseOptimizer.h"
#include "smap/slam/ProjectionSearch.h"
#include "smap/slam/Relocalisation.h"

namespace smap::slam
{
using Clock = core::SteadyClock;
using core::millisecondsSince;

std::string toString(TrackingStatus s)
{
    switch (s)
    {
        case TrackingStatus::NotInitialised:
            return "not_initialised";
        case TrackingStatus::Initialised:
            return "initialised";
        case TrackingStatus::Ok:
            return "ok";
        case TrackingStatus::Relocalised:
            return "relocalised";
        case TrackingStatus::Reanchored:
            return "reanchored";
        case TrackingStatus::Odometry:
            return "odometry";
        case TrackingStatus::Lost:
            return "lost";
        case TrackingStatus::Discarded:
            return "discarded";
    }
    return "unknown";
}

std::string toString(TrackingFallback f)
{
    switch (f)
    {
        case TrackingFallback::None:
            return "";
        case TrackingFallback::RaisedWeights:
            return "raised_weights";
        case TrackingFallback::StillMovable:
            return "still_movable";
        case TrackingFallback::CarriedPose:
            return "carried_pose";
    }
    return "unknown";
}

Tracker::Tracker(Map& map, LocalMapper& mapper, const TrackerParameters& params)
    : COutputLogger("tracking"), map_(map), mapper_(mapper), params_(params)
{
}

int Tracker::optimise(Frame& frame)
{
    const auto t0 = Clock::now();
    const int n = optimizePose(frame, params_.optimisation_rounds, params_.optimisation_iterations);
    timings_.optimisation_ms += millisecondsSince(t0);
    return n;
}

TrackingResult Tracker::track(Frame frame)
{
    const auto t0 = Clock::now();
    const double cpu0 = core::threadCpuMilliseconds();
    timings_ = {};
    TrackingResult result;
    result.keypoints = static_cast<int>(frame.size());
    if (frame.weights.size() != frame.size())
        frame.setWeights({});
    if (frame.mappable.size() != frame.size())
        frame.mappable.clear();
    frame.clearMatches();
    std::shared_ptr<KeyFrame> newKf;
    {
        const auto tLock = Clock::now();
        applyPendingMerge();
        map_.beginTrackingWait();
        std::lock_guard<std::mutex> lock(map_.mutex());
        map_.endTrackingWait();
        timings_.map_wait_ms = millisecondsSince(tLock);
        followLoopCorrection();
        newKf = state_ == TrackerState::NotInitialised ? startMap(frame, result)
                                                       : trackOnMap(frame, result);
        record(frame, result);
        if (reference_)
            T_reference_world_seen_ = reference_->resolvedT_cam_world();
    }
    result.newKeyFrame = newKf != nullptr;
    if (newKf)
        result.keyFrameId = newKf->id();
    last_ = std::move(frame);
    timings_.total_ms = millisecondsSince(t0);
    timings_.cpu_ms = core::threadCpuMilliseconds() - cpu0;
    timings_.matching_ms =
        std::max(0.0, timings_.total_ms - timings_.optimisation_ms - timings_.map_wait_ms);
    result.timings = timings_;
    // Outside the map lock: a synchronous local mapper processes the keyframe right here
    // (its time is local mapping's, reported by LocalMapper::stats(), not tracking's).
    if (newKf)
        mapper_.insertKeyFrame(newKf);
    return result;
}

void Tracker::followLoopCorrection()
{
    if (map_.corrections() == correctionsSeen_)
        return;
    correctionsSeen_ = map_.corrections();
    if (!reference_)
        return;
    // T_cam_world_new = T_cam_reference * T_reference_world_new = T_cam_world_old * C.
    const Eigen::Isometry3d C =
        T_reference_world_seen_.inverse() * reference_->resolvedT_cam_world();
    if (last_)
        last_->T_cam_world = last_->T_cam_world * C;
    if (lastTracked_T_cam_world_)
        lastTracked_T_cam_world_ = *lastTracked_T_cam_world_ * C;
    for (auto& [id, T] : recentPoses_)
        T = T * C;
    MRPT_LOG_DEBUG_FMT("followed loop correction %lu",
                       static_cast<unsigned long>(correctionsSeen_));
}

std::shared_ptr<KeyFrame> Tracker::startMap(Frame& frame, TrackingResult& result)
{
    if (!initialise(frame))
        return nullptr;
    result.status = TrackingStatus::Initialised;
    result.posedEarlierFrameId = poseEarlierFrameFromOdometry(frame);
    return reference_;
}

std::shared_ptr<KeyFrame> Tracker::trackOnMap(Frame& frame, TrackingResult& result)
{
    if (last_)
        followReplacedPoints(*last_);
    const Attempt attempt =
        state_ == TrackerState::Lost ? trackWhileLost(frame) : trackWhileTracking(frame);
    const auto carried = odometryPose(frame);
    std::shared_ptr<KeyFrame> newKf;
    bool reanchored = false;
    if (!attempt.ok && state_ == TrackerState::Lost && params_.reanchor_after_s > 0.0 &&
        core::reached(frame.timestamp - lostSince_, params_.reanchor_after_s) &&
        lastTracked_T_cam_world_)
    {
        newKf = reanchor(frame, carried, result);
        reanchored = newKf != nullptr;
    }
    result.fallback = attempt.fallback;
    if (attempt.ok)
    {
        newKf = acceptTracked(frame, attempt.relocalised, result);
        probeOtherParts(frame);
    }
    else if (!reanchored)
        markLost(frame, result);
    if (attempt.relocalised)
        MRPT_LOG_INFO_FMT("relocalised at frame %lu", static_cast<unsigned long>(frame.id));
    rememberPose(frame, result, carried);
    return newKf;
}

Tracker::Attempt Tracker::trackWhileTracking(Frame& frame)
{
    bool ok = false;
    if (velocity_ && last_ && frame.id > lastRelocalisationFrameId_ + 1)
        ok = trackWithMotionModel(frame, *velocity_) || trackReferenceKeyFrame(frame);
    else
        // No velocity yet (just relocalised or re-anchored): the reference keyframe, else the
        // last frame's points around its pose (the camera moved little).
        ok = trackReferenceKeyFrame(frame) ||
             (last_ && trackWithMotionModel(frame, Eigen::Isometry3d::Identity()));
    if (ok)
        ok = trackLocalMap(frame);
    if (ok)
        return {true, false, TrackingFallback::None};
    for (const auto stage : {TrackingFallback::RaisedWeights, TrackingFallback::StillMovable})
        if (trackWithRaisedWeights(frame, stage) && nearPrediction(frame, stage))
            return {true, false, stage};
    if (trackFromCarriedPose(frame))
        return {true, false, TrackingFallback::CarriedPose};
    return {false, false, TrackingFallback::None};
}

Tracker::Attempt Tracker::trackWhileLost(Frame& frame)
{
    if (trackFromCarriedPose(frame))
        return {true, false, TrackingFallback::CarriedPose};
    const bool relocalised = relocalise(frame);
    if (relocalised)
    {
        lastRelocalisationFrameId_ = frame.id;
        lastRelocalisationTime_ = frame.timestamp;
    }
    return {relocalised && trackLocalMap(frame), relocalised};
}

std::shared_ptr<KeyFrame> Tracker::reanchor(Frame& frame,
                                            const std::optional<Eigen::Isometry3d>& carried,
                                            TrackingResult& result)
{
    // The pose the outside odometry carried forward; without it, constant velocity from the
    // last tracked frame for at most reanchor_after_s (a longer extrapolation only adds error).
    Eigen::Isometry3d T = *lastTracked_T_cam_world_;
    if (carried)
        T = *carried;
    else if (velocityAtLoss_)
        for (int k = 0; k < extrapolationSteps(frame); ++k)
            T = *velocityAtLoss_ * T;
    frame.T_cam_world = T;
    frame.clearMatches();
    if (!anchorKeyFrame(frame, params_.reanchor_min_points, true))
        return nullptr;
    MRPT_LOG_WARN_FMT("re-anchored at frame %lu after %d lost frames: part %u of the map",
                      static_cast<unsigned long>(frame.id), framesLost_, reference_->part());
    state_ = TrackerState::Tracking;
    framesLost_ = 0;
    velocity_.reset();
    lastTracked_T_cam_world_ = frame.T_cam_world;
    lastTrackedTime_ = frame.timestamp;
    result.status = TrackingStatus::Reanchored;
    return reference_;
}

std::shared_ptr<KeyFrame> Tracker::acceptTracked(Frame& frame, bool relocalised,
                                                 TrackingResult& result)
{
    result.status = relocalised ? TrackingStatus::Relocalised : TrackingStatus::Ok;
    if (last_ && state_ != TrackerState::Lost)
    {
        velocity_ = frame.T_cam_world * last_->T_cam_world.inverse();
        velocityInterval_ = frame.timestamp - last_->timestamp;
    }
    else
        velocity_.reset();
    std::shared_ptr<KeyFrame> newKf;
    if (needNewKeyFrame(frame))
        newKf = createKeyFrame(frame);
    frame.discardOutliers();
    state_ = TrackerState::Tracking;
    framesLost_ = 0;
    lastTracked_T_cam_world_ = frame.T_cam_world;
    lastTrackedTime_ = frame.timestamp;
    return newKf;
}

void Tracker::markLost(const Frame& frame, TrackingResult& result)
{
    if (state_ != TrackerState::Lost)
    {
        MRPT_LOG_WARN_FMT("tracking lost at frame %lu (t = %.3f)",
                          static_cast<unsigned long>(frame.id), frame.timestamp);
        velocityAtLoss_ = velocity_;
        velocityIntervalAtLoss_ = velocityInterval_;
        lostSince_ = frame.timestamp;
    }
    result.status = TrackingStatus::Lost;
    velocity_.reset();
    state_ = TrackerState::Lost;
    framesLost_++;
}

void Tracker::rememberPose(const Frame& frame, const TrackingResult& result,
                           const std::optional<Eigen::Isometry3d>& carried)
{
    constexpr size_t kRecentPoses = 16;
    if (hasPose(result.status))
        recentPoses_.emplace_back(frame.id, frame.T_cam_world);
    else if (carried)
        recentPoses_.emplace_back(frame.id, *carried);
    while (recentPoses_.size() > kRecentPoses)
        recentPoses_.pop_front();
}

void Tracker::record(const Frame& frame, TrackingResult& result)
{
    result.inliers = frame.countMatches();
    result.frameId = frame.id;
    FrameRecord rec;
    rec.frameId = frame.id;
    rec.timestamp = frame.timestamp;
    rec.status = result.status;
    if (hasPose(result.status) && reference_)
    {
        rec.reference = reference_;
        rec.T_cam_reference = frame.T_cam_world * reference_->T_cam_world().inverse();
        result.T_world_cam = frame.T_cam_world.inverse();
    }
    records_.push_back(rec);
}

std::vector<uint64_t> Tracker::dropDiscardedPoses()
{
    std::vector<uint64_t> dropped;
    for (auto& r : records_)
    {
        if (!hasPose(r.status) || !r.reference || !map_.isDiscarded(r.reference->part()))
            continue;
        r.status = TrackingStatus::Discarded;
        r.reference.reset();
        dropped.push_back(r.frameId);
    }
    return dropped;
}

std::optional<uint64_t> Tracker::poseEarlierFrameFromOdometry(const Frame& frame)
{
    if (!frame.odometry_T_cam_earlier || frame.odometryFramesBack == 0 ||
        frame.odometryFramesBack > frame.id)
        return std::nullopt;
    const uint64_t earlier = frame.id - frame.odometryFramesBack;
    const auto rec = std::find_if(records_.begin(), records_.end(),
                                  [earlier](const FrameRecord& r) { return r.frameId == earlier; });
    if (rec == records_.end() || rec->status != TrackingStatus::NotInitialised)
        return std::nullopt;
    // The odometry's pose, refined against the new map when the earlier frame is still at
    // hand: the map holds only keypoints the outside vetted, so the earlier frame's keypoints
    // may all take part (its own weights are what kept it from starting the map).
    Eigen::Isometry3d T_earlier_world = frame.odometry_T_cam_earlier->inverse() * frame.T_cam_world;
    if (last_ && last_->id == earlier)
    {
        Frame& e = *last_;
        const std::vector<float> weights = e.weights;
        std::fill(e.weights.begin(), e.weights.end(), 1.0F);
        const int inliers = poseFromReferenceKeyFrame(e, T_earlier_world);
        if (inliers >= params_.min_inliers)
            T_earlier_world = e.T_cam_world;
        MRPT_LOG_DEBUG_FMT("frame %lu posed from the odometry%s (%d inliers against the map)",
                           static_cast<unsigned long>(earlier),
                           inliers >= params_.min_inliers ? ", refined" : "", inliers);
        e.weights = weights;
        e.clearMatches();
    }
    rec->status = TrackingStatus::Odometry;
    rec->reference = reference_;
    rec->T_cam_reference = T_earlier_world * reference_->T_cam_world().inverse();
    return earlier;
}

std::optional<Eigen::Isometry3d> Tracker::odometryPose(const Frame& frame) const
{
    if (!frame.odometry_T_cam_earlier || frame.odometryFramesBack == 0 ||
        frame.odometryFramesBack > frame.id)
        return std::nullopt;
    const uint64_t earlier = frame.id - frame.odometryFramesBack;
    for (const auto& [id, T] : recentPoses_)
        if (id == earlier)
            return *frame.odometry_T_cam_earlier * T;
    return std::nullopt;
}

bool Tracker::initialise(Frame& frame)
{
    frame.T_cam_world = Eigen::Isometry3d::Identity();
    if (!anchorKeyFrame(frame, params_.init_min_points, false))
        return false;
    state_ = TrackerState::Tracking;
    lastTracked_T_cam_world_ = frame.T_cam_world;
    lastTrackedTime_ = frame.timestamp;
    recentPoses_.emplace_back(frame.id, frame.T_cam_world);
    MRPT_LOG_INFO_FMT("map initialised at frame %lu with %zu points",
                      static_cast<unsigned long>(frame.id), map_.points().size());
    return true;
}

bool Tracker::anchorKeyFrame(Frame& frame, int min_points, bool newPart)
{
    // The first frame has no motion evidence yet: its usable keypoints start the map. A
    // re-anchor happens amid what lost tracking (people filling the view): only keypoints
    // shown static start it, as at any other keyframe.
    const auto starts = [&](size_t i)
    { return (newPart ? frame.canMap(i) : frame.usable(i)) && frame.features.hasDepth(i); };
    int withDepth = 0;
    for (size_t i = 0; i < frame.size(); ++i)
        if (starts(i))
            withDepth++;
    if (withDepth < min_points)
        return false;
    auto kf = map_.createKeyFrame(frame);
    if (newPart)
    {
        kf->setPart(map_.newPart());
        kf->setPartOrigin(true);
    }
    const Eigen::Isometry3d T_world_cam = frame.T_cam_world.inverse();
    for (size_t i = 0; i < frame.size(); ++i)
    {
        if (!starts(i))
            continue;
        const auto& p = frame.features.undistorted[i];
        auto mp = map_.createPoint(
            T_world_cam * frame.camera.unproject(p.x, p.y, frame.features.depth[i]), kf.get());
        mp->addObservation(kf.get(), i);
        kf->points[i] = mp;
        frame.points[i] = mp;
        mp->computeDistinctiveDescriptor();
        mp->updateNormalAndDepth();
    }
    reference_ = kf;
    lastKeyFrameTime_ = frame.timestamp;
    localKeyFrames_ = {kf.get()};
    return true;
}

void Tracker::followReplacedPoints(Frame& frame) const
{
    for (auto& mp : frame.points)
    {
        while (mp && mp->replacement())
            mp = mp->replacement();
        if (mp && mp->isBad())
            mp.reset();
    }
}

bool Tracker::trackWithMotionModel(Frame& frame, const Eigen::Isometry3d& velocity)
{
    frame.T_cam_world = velocity * last_->T_cam_world;
    frame.clearMatches();
    int n = searchFromLastFrame(frame, *last_, params_.motion_search_radius);
    if (n < params_.min_matches_motion)
    {
        frame.clearMatches();
        n = searchFromLastFrame(frame, *last_, 2.0 * params_.motion_search_radius);
    }
    if (n < params_.min_matches_motion)
        return false;
    optimise(frame);
    return frame.discardOutliers() >= 10;
}

bool Tracker::trackWithRaisedWeights(Frame& frame, TrackingFallback stage)
{
    if (params_.fallback_weight <= 0.0 || !last_)
        return false;
    const auto floor = static_cast<float>(params_.fallback_weight);
    // What this stage raises: every keypoint below the floor outside movable regions, and at
    // the last stage the still ones inside them.
    std::vector<size_t> raised;
    bool anyBelowFloor = false, raisesMovable = false;
    for (size_t i = 0; i < frame.weights.size(); ++i)
    {
        if (frame.weights[i] >= floor)
            continue;
        anyBelowFloor = true;
        const bool movable = i < frame.movable.size() && frame.movable[i];
        const bool still = i < frame.stillMovable.size() && frame.stillMovable[i];
        if (movable && !(stage == TrackingFallback::StillMovable && still))
            continue;
        raised.push_back(i);
        raisesMovable = raisesMovable || movable;
    }
    // The still-movable stage only adds to the raised-weights stage, which failed already.
    if (!anyBelowFloor || (stage == TrackingFallback::StillMovable && !raisesMovable))
        return false;  // nothing would change
    const std::vector<float> weights = frame.weights;
    for (const size_t i : raised)
        frame.weights[i] = floor;
    const bool ok =
        trackWithMotionModel(frame, velocity_ ? *velocity_ : Eigen::Isometry3d::Identity()) &&
        trackLocalMap(frame);
    // Back to the outside weights: excluded keypoints keep their matches for this pose, but
    // start no map point and carry no weight in bundle adjustment.
    frame.weights = weights;
    if (ok)
        MRPT_LOG_DEBUG_FMT("frame %lu tracked by the %s fallback (%d inliers)",
                           static_cast<unsigned long>(frame.id), toString(stage).c_str(),
                           frame.countMatches());
    return ok;
}

bool Tracker::nearPrediction(const Frame& frame, TrackingFallback stage) const
{
    if (!velocity_ || !last_ ||
        (params_.fallback_max_jump <= 0.0 && params_.fallback_max_jump_deg <= 0.0))
        return true;
    const Eigen::Isometry3d T_predicted_cam =
        (*velocity_ * last_->T_cam_world) * frame.T_cam_world.inverse();
    // A longer gap since the last frame (a dropped frame) allows a proportionally larger jump.
    const double elapsed = frame.timestamp - last_->timestamp;
    const double scale = velocityInterval_ > 0.0 ? std::max(1.0, elapsed / velocityInterval_) : 1.0;
    const double jump = T_predicted_cam.translation().norm();
    const double jumpDeg = Eigen::AngleAxisd(T_predicted_cam.linear()).angle() * 180.0 / M_PI;
    const bool near =
        (params_.fallback_max_jump <= 0.0 || jump <= scale * params_.fallback_max_jump) &&
        (params_.fallback_max_jump_deg <= 0.0 || jumpDeg <= scale * params_.fallback_max_jump_deg);
    if (!near)
        MRPT_LOG_INFO_FMT(
            "frame %lu: the %s fallback's pose is %.3f m / %.2f deg from the "
            "constant-velocity prediction; not kept",
            static_cast<unsigned long>(frame.id), toString(stage).c_str(), jump, jumpDeg);
    return near;
}

bool Tracker::trackReferenceKeyFrame(Frame& frame)
{
    return last_ && poseFromReferenceKeyFrame(frame, last_->T_cam_world) >= 10;
}

int Tracker::poseFromReferenceKeyFrame(Frame& frame, const Eigen::Isometry3d& T_cam_world_guess)
{
    frame.clearMatches();
    if (!reference_ || reference_->isBad())
        return 0;
    const KeyFrame& kf = *reference_;
    const std::vector<size_t> kfRows = kf.keypointsWithPoints(),
                              frameRows = frame.usableKeypoints();
    if (kfRows.empty() || frameRows.empty())
        return 0;
    const auto matches =
        features::matchWithRatioTest(frame.features.descriptors, kf.features.descriptors, 0.7F,
                                     kDescriptorHigh, frameRows, kfRows);
    features::RotationConsistency rot;
    for (const auto& m : matches)
    {
        frame.points[m.query] = kf.points[m.train];
        rot.add(m.query, kf.features.keypoints[m.train].angle,
                frame.features.keypoints[m.query].angle);
    }
    int n = static_cast<int>(matches.size());
    for (size_t i : rot.inconsistent())
    {
        frame.points[i].reset();
        n--;
    }
    if (n < 15)
        return 0;
    frame.T_cam_world = T_cam_world_guess;
    optimise(frame);
    return frame.discardOutliers();
}

bool Tracker::relocalise(Frame& frame)
{
    frame.clearMatches();
    const int inliers = relocaliseFrame(frame, map_, params_, reference_.get(), framesLost_);
    return inliers >= params_.min_inliers_after_relocalisation;
}

void Tracker::probeOtherParts(const Frame& frame)
{
    if (map_.liveParts().size() < 2 || !reference_ || pendingMerge_)
        return;
    const uint32_t part = reference_->part();
    Frame probe = frame;
    probe.clearMatches();
    const auto other = relocaliseInOtherPart(probe, map_, params_, part, partProbes_++);
    if (!other)
        return;
    PartMerge m;
    m.frameId = frame.id;
    m.inliers = probe.countMatches();
    // The frame in both frames: T_other_part = T_cam_other^-1 * T_cam_part.
    const Eigen::Isometry3d T_other_part = probe.T_cam_world.inverse() * frame.T_cam_world;
    m.from = std::max(part, *other);
    m.to = std::min(part, *other);
    m.T_to_from = m.from == part ? T_other_part : T_other_part.inverse();
    pendingMerge_ = m;
}

void Tracker::applyPendingMerge()
{
    if (!pendingMerge_)
        return;
    const PartMerge m = *pendingMerge_;
    pendingMerge_.reset();
    std::lock_guard<std::mutex> still(mapper_.processingMutex());
    std::lock_guard<std::mutex> lock(map_.mutex());
    if (!map_.liveParts().count(m.from) || !map_.liveParts().count(m.to))
        return;
    map_.mergePart(m.from, m.to, m.T_to_from);
    MRPT_LOG_WARN_FMT(
        "frame %lu placed part %u of the map in part %u (%d inliers): merged, "
        "moved by %.3f m / %.1f deg",
        static_cast<unsigned long>(m.frameId), m.from, m.to, m.inliers,
        m.T_to_from.translation().norm(),
        Eigen::AngleAxisd(m.T_to_from.linear()).angle() * 180.0 / M_PI);
}

bool Tracker::trackFromCarriedPose(Frame& frame)
{
    if (params_.carried_search_s <= 0.0 ||
        (state_ == TrackerState::Lost &&
         core::reached(frame.timestamp - lostSince_, params_.carried_search_s)))
        return false;
    const auto carried = odometryPose(frame);
    if (!carried)
        return false;
    frame.clearMatches();
    frame.T_cam_world = *carried;
    updateLocalMap(frame);  // no matches yet: all the points of the last local keyframes
    const int found = searchLocalPoints(frame, localPoints_, params_.local_search_radius);
    const int needed =
        state_ == TrackerState::Lost ? params_.carried_min_inliers : params_.min_inliers;
    const bool ok = found >= params_.min_matches_motion && optimise(frame) > 0 &&
                    frame.discardOutliers() >= 10 && trackLocalMap(frame) &&
                    frame.countMatches() >= needed;
    if (!ok)
        frame.clearMatches();
    return ok;
}

void Tracker::updateLocalMap(const Frame& frame)
{
    std::map<uint64_t, std::pair<KeyFrame*, int>> counts;
    for (size_t i = 0; i < frame.size(); ++i)
    {
        const auto& mp = frame.points[i];
        if (!mp || frame.outlier[i] || mp->isBad())
            continue;
        for (const auto& [kfId, o] : mp->observations())
        {
            auto& c = counts[kfId];
            c.first = o.keyframe;
            c.second++;
        }
    }
    if (counts.empty())
    {
        collectLocalPoints(frame);
        return;
    }
    localKeyFrames_.clear();
    std::set<uint64_t> inLocal;
    int best = -1;
    KeyFrame* bestKf = nullptr;
    for (const auto& [id, c] : counts)
    {
        if (c.first->isBad())
            continue;
        localKeyFrames_.push_back(c.first);
        inLocal.insert(id);
        if (c.second > best)
        {
            best = c.second;
            bestKf = c.first;
        }
    }
    constexpr size_t kMaxLocal = 80;
    const size_t nDirect = localKeyFrames_.size();
    for (size_t k = 0; k < nDirect && localKeyFrames_.size() < kMaxLocal; ++k)
        for (KeyFrame* n : localKeyFrames_[k]->bestCovisibles(10))
            if (!n->isBad() && inLocal.insert(n->id()).second)
                localKeyFrames_.push_back(n);
    if (bestKf)
        reference_ = map_.allKeyFrames().at(bestKf->id());
    if (params_.revisit_radius > 0.0)
        joinRevisitedKeyFrames(frame, inLocal);

    collectLocalPoints(frame);
}

// The points of the local keyframes, each once, in keyframe order, less those the frame
// already tracks. A mark per search instead of a set: this runs on every frame over all the
// local keyframes' points.
void Tracker::collectLocalPoints(const Frame& frame)
{
    const uint64_t search = ++localSearch_;
    for (size_t i = 0; i < frame.size(); ++i)
        if (frame.points[i] && !frame.outlier[i])
            frame.points[i]->markForSearch(search);
    localPoints_.clear();
    for (KeyFrame* kf : localKeyFrames_)
        for (const auto& mp : kf->points)
            if (mp && !mp->isBad() && mp->markForSearch(search))
                localPoints_.push_back(mp);
}

// Keyframes that saw this place earlier but share no tracked points (the camera came back
// after a detour): their points join the local map, so revisits match old points, fusion
// links old and new keyframes, and local BA pulls them together.
// Places older than revisit_max_age_s are left to loop closing.
void Tracker::joinRevisitedKeyFrames(const Frame& frame, std::set<uint64_t>& inLocal)
{
    const Eigen::Isometry3d T_world_cam = frame.T_cam_world.inverse();
    const Eigen::Vector3d centre = T_world_cam.translation();
    const Eigen::Vector3d axis = T_world_cam.linear().col(2);
    std::vector<std::pair<double, KeyFrame*>> near;
    for (const auto& [id, kf] : map_.keyframes())
    {
        if (kf->isBad() || inLocal.count(id) || tooOldForRevisit(frame, *kf) ||
            (reference_ && kf->part() != reference_->part()))
            continue;
        const Eigen::Isometry3d T_world_kf = kf->T_cam_world().inverse();
        const double d = (T_world_kf.translation() - centre).norm();
        if (d < params_.revisit_radius && T_world_kf.linear().col(2).dot(axis) > 0.8)
            near.emplace_back(d, kf.get());
    }
    std::sort(near.begin(), near.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (size_t k = 0; k < near.size() && k < 10; ++k)
    {
        inLocal.insert(near[k].second->id());
        localKeyFrames_.push_back(near[k].second);
    }
}

bool Tracker::recentlyRelocalised(const Frame& frame) const
{
    return lastRelocalisationFrameId_ > 0 &&
           !core::reached(frame.timestamp - lastRelocalisationTime_,
                          params_.keyframe_max_interval_s);
}

int Tracker::extrapolationSteps(const Frame& frame) const
{
    // One step of the velocity at the loss per frame interval since the last tracked frame, as
    // far as reanchor_after_s (and one step more, to the frame itself).
    if (!(velocityIntervalAtLoss_ > 0.0))
        return framesLost_ + 1;
    const double span = std::min(frame.timestamp - lastTrackedTime_,
                                 params_.reanchor_after_s + velocityIntervalAtLoss_);
    return std::max(1, static_cast<int>(std::lround(span / velocityIntervalAtLoss_)));
}

bool Tracker::tooOldForRevisit(const Frame& frame, const KeyFrame& kf) const
{
    return params_.revisit_max_age_s > 0.0 &&
           frame.timestamp - kf.timestamp() > params_.revisit_max_age_s + core::kTimeTolerance_s;
}

bool Tracker::trackLocalMap(Frame& frame)
{
    updateLocalMap(frame);
    for (size_t i = 0; i < frame.size(); ++i)
        if (frame.points[i] && !frame.outlier[i])
            frame.points[i]->increaseVisible();
    const double radius =
        frame.id < lastRelocalisationFrameId_ + 2 && lastRelocalisationFrameId_ > 0
            ? 5.0
            : params_.local_search_radius;
    searchLocalPoints(frame, localPoints_, radius);
    optimise(frame);
    int inliers = 0;
    for (size_t i = 0; i < frame.size(); ++i)
    {
        const auto& mp = frame.points[i];
        if (!mp || frame.outlier[i])
            continue;
        mp->increaseFound();
        if (mp->numObservations() > 0)
            inliers++;
    }
    if (recentlyRelocalised(frame) && inliers < params_.min_inliers_after_relocalisation)
        return false;
    return inliers >= params_.min_inliers;
}

bool Tracker::needNewKeyFrame(const Frame& frame) const
{
    // ORB-SLAM pauses keyframes after a relocalisation once the map holds more keyframes than
    // its frame rate (30).
    constexpr size_t kLargeMapKeyFrames = 30;
    const size_t nKfs = map_.keyframes().size();
    if (recentlyRelocalised(frame) && nKfs > kLargeMapKeyFrames)
        return false;
    // ORB-SLAM counts an RGB-D observation twice; in keyframes its thresholds are 1 and 2.
    const int nMinObs = nKfs <= 2 ? 1 : 2;
    const int refMatches = reference_ ? reference_->trackedPoints(nMinObs) : 0;
    const bool idle = mapper_.idle();

    int trackedClose = 0, untrackedClose = 0, inliers = 0;
    for (size_t i = 0; i < frame.size(); ++i)
    {
        const bool tracked = frame.points[i] && !frame.outlier[i];
        if (tracked)
            inliers++;
        const float z = frame.features.depth[i];
        if (!frame.usable(i) || z <= 0.0F || z > frame.closeDepth)
            continue;
        (tracked ? trackedClose : untrackedClose)++;
    }
    const bool needClose = trackedClose < 100 && untrackedClose > 70;
    const double refRatio = nKfs < 2 ? 0.4 : params_.keyframe_ref_ratio;
    const double sinceKeyFrame = frame.timestamp - lastKeyFrameTime_;
    const bool c1a = core::reached(sinceKeyFrame, params_.keyframe_max_interval_s);
    const bool c1b = idle && core::reached(sinceKeyFrame, params_.keyframe_min_interval_s);
    const bool c1c = inliers < 0.25 * refMatches || needClose;
    const bool c2 = (inliers < refRatio * refMatches || needClose) && inliers > 15;
    if (!((c1a || c1b || c1c) && c2))
        return false;
    if (idle)
        return true;
    mapper_.interruptBundleAdjustment();
    return mapper_.queued() < 3;
}

std::shared_ptr<KeyFrame> Tracker::createKeyFrame(Frame& frame)
{
    auto kf = map_.createKeyFrame(frame);
    kf->setPart(reference_ ? reference_->part() : 0U);
    // Tracked points (outliers included: bundle adjustment decides) ...
    for (size_t i = 0; i < frame.size(); ++i)
        kf->points[i] = frame.points[i];
    // ... and new points from depth, nearest first: all close ones, at least
    // keyframe_new_points.
    std::vector<std::pair<float, size_t>> byDepth;
    for (size_t i = 0; i < frame.size(); ++i)
        if (frame.canMap(i) && frame.features.hasDepth(i))
            byDepth.emplace_back(frame.features.depth[i], i);
    std::sort(byDepth.begin(), byDepth.end());
    const Eigen::Isometry3d T_world_cam = frame.T_cam_world.inverse();
    int n = 0;
    for (const auto& [z, i] : byDepth)
    {
        const auto& existing = frame.points[i];
        if (!existing || existing->numObservations() == 0)
        {
            const auto& p = frame.features.undistorted[i];
            auto mp = map_.createPoint(T_world_cam * frame.camera.unproject(p.x, p.y, z), kf.get());
            mp->addObservation(kf.get(), i);
            kf->points[i] = mp;
            frame.points[i] = mp;
            frame.outlier[i] = false;
            mp->computeDistinctiveDescriptor();
            mp->updateNormalAndDepth();
        }
        n++;
        if (z > frame.closeDepth && n > params_.keyframe_new_points)
            break;
    }
    reference_ = kf;
    lastKeyFrameTime_ = frame.timestamp;
    return kf;
}
}  // namespace smap::slam
