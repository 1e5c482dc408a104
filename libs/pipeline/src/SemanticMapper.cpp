#include "smap/pipeline/SemanticMapper.h"

#include <map>
#include <opencv2/core.hpp>

#include "smap/core/Elapsed.h"
#include "smap/core/RecordingTime.h"
#include "smap/dynamic/MovableVerdict.h"

namespace smap::pipeline
{
namespace
{
SemanticMapperParameters withReproducibleMode(SemanticMapperParameters params)
{
    params.applyReproducibleMode();
    return params;
}
}  // namespace

SemanticMapper::SemanticMapper(const SemanticMapperParameters& params)
    : SemanticMapper(params, segmentation::makeSegmenter(params.segmentation))
{
}

SemanticMapper::SemanticMapper(const SemanticMapperParameters& params,
                               std::unique_ptr<segmentation::Segmenter> segmenter)
    : COutputLogger("semantic-mapper"),
      params_(withReproducibleMode(params)),
      slam_(std::make_unique<slam::RgbdSlam>(params_.orb, params_.tracking, params_.localMapping,
                                             params_.loopClosing)),
      dynamicFilter_(params_.dynamic),
      labelTracker_(params_.semanticEvidence.max_mask_age_s + params_.dynamic.frame_gap_s +
                        kLabelHistoryMargin_s,
                    params_.semanticEvidence.depth_margin),
      profiler_(true, "semantic-mapper")
{
    profiler_.setMinLoggingLevel(mrpt::system::LVL_ERROR);  // no statistics dump on exit
    worker_ = std::make_unique<KeyFrameWorker>(
        std::move(segmenter), segmentation::loadLabelSet(params_.segmentation), params_.association,
        params_.map, static_cast<size_t>(params_.pipeline.keyframe_queue));
    if (semanticEvidenceOn())
    {
        worker_->setMaskBoard(
            &maskBoard_, worker_->labels().movable(params_.semanticEvidence.movable_prior),
            params_.semanticEvidence.sample_step, params_.semanticEvidence.mask_latency_s == 0.0);
    }
}

SemanticMapper::~SemanticMapper() = default;

void SemanticMapper::setKeyFrameObserver(KeyFrameWorker::Observer observer)
{
    worker_->setObserver(std::move(observer));
}

double SemanticMapper::increasingTimestamp(double timestamp)
{
    // Time parameters count seconds of the recording: a source whose timestamps stall or run
    // backwards would stop keyframes and age no mask. Such frames get the nominal interval.
    constexpr double kNominalInterval_s = 1.0 / 30.0;
    if (lastTimestamp_ && !(timestamp > *lastTimestamp_))
    {
        if (!timestampWarned_)
            MRPT_LOG_WARN_FMT(
                "frame timestamp %.6f s is not after the previous frame's (%.6f s): "
                "frames without increasing timestamps are taken %.3f s apart",
                timestamp, *lastTimestamp_, kNominalInterval_s);
        timestampWarned_ = true;
        timestamp = *lastTimestamp_ + kNominalInterval_s;
    }
    lastTimestamp_ = timestamp;
    return timestamp;
}

SemanticMapper::PreparedFrame SemanticMapper::prepare(const core::RgbdFrame& frame)
{
    PreparedFrame p;
    p.rgbd = frame;
    p.rgbd.timestamp = increasingTimestamp(frame.timestamp);
    const auto t0 = std::chrono::steady_clock::now();
    // Regions the previous frame found moving get features last (people filling most of the
    // view would otherwise take most of the budget from the background).
    p.features = slam_->prepare(p.rgbd, dynamicFilter_.moverRegions());
    p.extraction_ms = core::millisecondsSince(t0);
    p.dynamic = dynamicFilter_.process(frame.colour, frame.depth, p.features.features, frame.camera,
                                       p.rgbd.timestamp);
    profiler_.registerUserMeasure("frame.extraction", p.extraction_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.dynamic", p.dynamic.total_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.dynamic.ego_motion", p.dynamic.ego_motion_ms / 1000.0,
                                  true);
    profiler_.registerUserMeasure("frame.dynamic.warp", p.dynamic.warp_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.dynamic.flow", p.dynamic.flow_ms / 1000.0, true);
    p.features.setWeights(p.dynamic.weights());
    p.features.setMappable(p.dynamic.mappable());
    if (p.dynamic.egoMotion.valid && p.dynamic.framesBack > 0)
    {
        p.features.odometry_T_cam_earlier = p.dynamic.egoMotion.T_cur_prev;
        p.features.odometryFramesBack = p.dynamic.framesBack;
    }
    return p;
}

SemanticMapper::FrameResult SemanticMapper::track(
    PreparedFrame frame, const std::function<void(const PreparedFrame&)>& inspect)
{
    FrameResult r;
    // S of Algorithm 1: the keypoints the motion evidence calls dynamic, taken before the
    // semantic evidence adds the movable ones. Algorithm 1 removes movable-class objects of
    // the keyframe's own segmentation whole; a movable keypoint of an older mask, grown and
    // warped, would only add discs of background around the person.
    std::vector<mapping::DynamicPoint> dynamicPoints = movingKeypoints(frame);
    const auto t0 = std::chrono::steady_clock::now();
    applySemanticEvidence(frame, r);
    r.semantic_ms = core::millisecondsSince(t0);
    profiler_.registerUserMeasure("frame.semantic", r.semantic_ms / 1000.0, true);
    if (inspect)
        inspect(frame);
    r.dynamicKeypoints = frame.dynamic.numDynamic();
    r.dynamic_ms = frame.dynamic.total_ms;

    r.tracking = slam_->track(std::move(frame.features));
    r.tracking.timings.extraction_ms = frame.extraction_ms;
    profiler_.registerUserMeasure("frame.tracking", r.tracking.timings.total_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.tracking.optimisation",
                                  r.tracking.timings.optimisation_ms / 1000.0, true);
    if (slam::hasPose(r.tracking.status))
    {
        recentPoses_.emplace_back(r.tracking.frameId, r.tracking.T_world_cam);
        if (recentPoses_.size() > 2)
            recentPoses_.pop_front();
    }
    if (r.tracking.newKeyFrame && slam::hasPose(r.tracking.status))
        submitKeyFrame(frame, std::move(dynamicPoints), r);
    framesTracked_++;
    return r;
}

std::vector<mapping::DynamicPoint> SemanticMapper::movingKeypoints(const PreparedFrame& frame)
{
    std::vector<mapping::DynamicPoint> points;
    const auto& fs = frame.features.features;
    for (size_t i = 0; i < frame.dynamic.keypoints.size() && i < fs.size(); ++i)
        if (frame.dynamic.keypoints[i].dynamic)
            points.push_back({fs.keypoints[i].pt.x, fs.keypoints[i].pt.y, fs.depth[i]});
    return points;
}

void SemanticMapper::submitKeyFrame(PreparedFrame& frame,
                                    std::vector<mapping::DynamicPoint> dynamicPoints,
                                    FrameResult& r)
{
    KeyFrameJob job;
    job.keyframe = r.tracking.keyFrameId.value_or(0);
    job.frameId = r.tracking.frameId;
    job.frame = std::move(frame.rgbd);
    job.T_world_cam = slam::toCPose3D(r.tracking.T_world_cam);
    job.dynamicPoints = std::move(dynamicPoints);
    const auto t0 = std::chrono::steady_clock::now();
    const uint64_t frameId = job.frameId;
    const bool queued =
        worker_->submit(std::move(job), params_.pipeline.when_full == WhenFull::Wait);
    if (queued && semanticEvidenceOn())
        maskBoard_.expect(frameId);
    r.queue_wait_ms = core::millisecondsSince(t0);
    profiler_.registerUserMeasure("frame.queue_wait", r.queue_wait_ms / 1000.0, true);
    r.keyframeDropped = !queued;
    keyframes_ += queued ? 1 : 0;
}

std::optional<Eigen::Isometry3d> SemanticMapper::predictPose(uint64_t frameId) const
{
    // Beyond a few frames the last pose says little about this one.
    constexpr uint64_t kMaxGap = 5;
    if (recentPoses_.empty() || frameId - recentPoses_.back().first > kMaxGap)
        return std::nullopt;
    const auto& [lastId, T_world_last] = recentPoses_.back();
    if (recentPoses_.size() < 2 || recentPoses_.front().first + 1 != lastId)
        return T_world_last;
    const Eigen::Isometry3d velocity = recentPoses_.front().second.inverse() * T_world_last;
    Eigen::Isometry3d T = T_world_last;
    for (uint64_t k = lastId; k < frameId; ++k)
        T = T * velocity;
    return T;
}

void SemanticMapper::rememberFrameTime(double timestamp)
{
    frameTimes_.emplace_back(framesTracked_, timestamp);
    const double keep_s = params_.semanticEvidence.max_mask_age_s + kLabelHistoryMargin_s;
    while (frameTimes_.size() > 1 && timestamp - frameTimes_.front().second > keep_s)
        frameTimes_.pop_front();
}

std::optional<uint64_t> SemanticMapper::newestFrameAtOrBefore(double timestamp) const
{
    for (auto it = frameTimes_.rbegin(); it != frameTimes_.rend(); ++it)
        if (it->second <= timestamp + core::kTimeTolerance_s)
            return it->first;
    return std::nullopt;
}

std::optional<double> SemanticMapper::frameTime(uint64_t frameId) const
{
    for (const auto& [id, t] : frameTimes_)
        if (id == frameId)
            return t;
    return std::nullopt;
}

std::vector<bool> SemanticMapper::movableKeypoints(const PreparedFrame& frame,
                                                   const MaskBoard::MaskPtr& mask, double age_s)
{
    // Every frame joins the label tracker, so that labels can follow people from the next mask.
    const auto& kps = frame.features.features.keypoints;
    dynamic::MovableLabelTracker::FrameTracks tracks;
    tracks.frameId = framesTracked_;
    tracks.timestamp = frame.rgbd.timestamp;
    tracks.framesBack = frame.dynamic.framesBack;
    tracks.keypoints.reserve(kps.size());
    tracks.inReference.assign(kps.size(), cv::Point2f(-1.0F, -1.0F));
    tracks.motion.assign(kps.size(), dynamic::MovableLabelTracker::Motion::Untracked);
    tracks.depth = frame.features.features.depth;
    for (size_t i = 0; i < kps.size(); ++i)
    {
        tracks.keypoints.push_back(kps[i].pt);
        if (i >= frame.dynamic.keypoints.size())
            continue;
        const dynamic::KeypointEvidence& e = frame.dynamic.keypoints[i];
        tracks.inReference[i] = e.inReference;
        if (e.residual >= 0.0F)
            tracks.motion[i] = e.flow ? dynamic::MovableLabelTracker::Motion::Moving
                                      : dynamic::MovableLabelTracker::Motion::Still;
    }
    if (mask && (!labelledMask_ || *labelledMask_ != mask->frameId()))
    {
        labelTracker_.setMask(mask->frameId(), mask->image());
        labelledMask_ = mask->frameId();
        keepStillParts(mask);
    }
    dynamic::MovableEvidence evidence;
    evidence.motion = tracks.motion;
    evidence.labels = labelTracker_.add(std::move(tracks));
    if (!mask)
        return std::vector<bool>(kps.size(), false);
    const slam::Frame& f = frame.features;
    evidence.pixels = f.features.undistorted;
    evidence.depth = f.features.depth;
    evidence.depthMargin = static_cast<float>(params_.semanticEvidence.depth_margin);
    // The masks warped by the camera pose: only the people who were still on the keyframe, for
    // whom the warp is right; a walker soon leaves it and the labels follow them instead.
    const std::optional<Eigen::Isometry3d> T_world_cam = predictPose(framesTracked_);
    if (T_world_cam)
    {
        const dynamic::SemanticEvidenceParameters& se = params_.semanticEvidence;
        const double grown =
            std::min(se.max_dilation_px, se.dilation_px + se.age_dilation_px_per_s * age_s);
        if (stillMask_ && !stillMask_->empty())
            evidence.grown = stillMask_->project(*T_world_cam, frame.rgbd.camera, grown);
        if (clearlyStillMask_ && !clearlyStillMask_->empty())
            evidence.still =
                clearlyStillMask_->project(*T_world_cam, frame.rgbd.camera, se.still_dilation_px);
    }
    return dynamic::movableVerdicts(evidence);
}

void SemanticMapper::keepStillParts(const MaskBoard::MaskPtr& mask)
{
    // Parts of the keyframe mask where more than two thirds of the measured keypoints moved are
    // walkers; at most still_part_max_moving, clearly still people.
    constexpr double kWalkerFraction = 2.0 / 3.0;
    auto without = [&mask](const cv::Mat& drop) -> std::shared_ptr<const dynamic::MovableMask>
    {
        if (cv::countNonZero(drop) == 0)
            return mask;
        return std::make_shared<const dynamic::MovableMask>(mask->without(drop));
    };
    const cv::Mat walking =
        labelTracker_.movingParts(mask->frameId(), mask->image(), kWalkerFraction);
    stillMask_ = without(walking);
    clearlyStillMask_.reset();
    const dynamic::SemanticEvidenceParameters& se = params_.semanticEvidence;
    if (se.still_dilation_px < 0.0)
        return;
    const cv::Mat moving =
        labelTracker_.movingParts(mask->frameId(), mask->image(), se.still_part_max_moving);
    clearlyStillMask_ =
        cv::countNonZero(moving) == cv::countNonZero(walking) ? stillMask_ : without(moving);
}

void SemanticMapper::applySemanticEvidence(PreparedFrame& frame, FrameResult& r)
{
    const dynamic::SemanticEvidenceParameters& se = params_.semanticEvidence;
    if (!semanticEvidenceOn())
        return;
    const double now = frame.rgbd.timestamp;
    rememberFrameTime(now);
    const bool wait = se.mask_latency_s > 0.0;
    const std::optional<uint64_t> upTo =
        wait ? newestFrameAtOrBefore(now - se.mask_latency_s) : framesTracked_;
    MaskBoard::Lookup lookup;
    if (upTo)
        lookup = maskBoard_.newest(*upTo, wait);
    r.mask_wait_ms = lookup.wait_ms;
    profiler_.registerUserMeasure("frame.mask_wait", r.mask_wait_ms / 1000.0, true);
    std::optional<double> maskTime;
    if (lookup.mask)
        maskTime = frameTime(lookup.mask->frameId());
    if (lookup.mask && (!maskTime || now - *maskTime > se.max_mask_age_s + core::kTimeTolerance_s))
        lookup.mask.reset();
    double age_s = 0.0;
    if (lookup.mask)
    {
        r.maskAge = framesTracked_ - lookup.mask->frameId();
        age_s = now - *maskTime;
    }
    const std::vector<bool> movable = movableKeypoints(frame, lookup.mask, age_s);
    markMovable(movable, frame, r);
}

void SemanticMapper::markMovable(const std::vector<bool>& movable, PreparedFrame& frame,
                                 FrameResult& r)
{
    slam::Frame& f = frame.features;
    const size_t n = f.size();
    f.movable = movable;
    if (f.weights.size() != n)
        f.weights.assign(n, 1.0F);
    f.stillMovable.assign(n, false);
    if (f.mappable.size() != n)
        f.mappable.assign(n, true);
    for (size_t i = 0; i < n; ++i)
    {
        if (!movable[i])
            continue;
        // Still: the motion evidence left it a weight before the semantic evidence takes it.
        f.stillMovable[i] = f.weights[i] > 0.0F;
        f.weights[i] = 0.0F;
        f.mappable[i] = false;
        if (i < frame.dynamic.keypoints.size())
        {
            frame.dynamic.keypoints[i].semantic = true;
            frame.dynamic.keypoints[i].dynamic = true;
        }
        r.movableKeypoints++;
    }
}

mapping::SemanticMapBuilder::ReanchorResult SemanticMapper::finish()
{
    slam_->finish();
    worker_->finish();
    const KeyFrameWorker::Stats ws = worker_->stats();
    for (const auto& [stage, times] : {std::pair{"keyframe.segmentation", &ws.segmentation_ms},
                                       std::pair{"keyframe.association", &ws.association_ms},
                                       std::pair{"keyframe.insertion", &ws.insertion_ms},
                                       std::pair{"keyframe.outputs", &ws.observer_ms}})
        for (const double ms : *times)
            profiler_.registerUserMeasure(stage, ms / 1000.0, true);
    // The final pose of every keyframe: its frame's pose through the refined keyframes (also
    // for a keyframe culled since).
    const std::map<uint64_t, mrpt::poses::CPose3D> finalPoses = slam_->framePoses();
    mapping::SemanticMapBuilder::ReanchorResult result;
    worker_->withMaps(
        [&](mapping::SemanticMapBuilder& b)
        {
            result = b.reanchor(
                [&](const mapping::KeyFrameContribution& c) -> std::optional<mrpt::poses::CPose3D>
                {
                    const auto it = finalPoses.find(c.frameId);
                    if (it == finalPoses.end())
                        return std::nullopt;
                    return it->second;
                },
                // Keyframes whose frame has no final pose: their part of the SLAM map was
                // dropped at the end (RgbdSlam::finish).
                [&](const mapping::KeyFrameContribution& c)
                { return finalPoses.count(c.frameId) == 0; });
            result.pruned = b.pruneFreePoints();
        });
    return result;
}
}  // namespace smap::pipeline
