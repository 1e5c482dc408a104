#include "smap/slam/RgbdSlam.h"

#include <mrpt/math/CMatrixFixed.h>

#include <chrono>
#include <map>
#include <set>

#include "smap/features/OrbExtractor.h"
#include "smap/slam/Map.h"

namespace smap::slam
{
namespace
{
/// [tracking] revisit_max_age_s = -1 follows loop closing: tracking joins the places loop
/// closing does not look at (younger than min_age_s), or every place when it is off.
TrackerParameters resolveRevisitAge(TrackerParameters tracking, const LoopClosingParameters& loop)
{
    if (tracking.revisit_max_age_s < 0.0)
        tracking.revisit_max_age_s = loop.enabled ? loop.min_age_s : 0.0;
    return tracking;
}
}  // namespace

RgbdSlam::RgbdSlam(const features::OrbParameters& orb, const TrackerParameters& tracking,
                   const LocalMappingParameters& mapping, const LoopClosingParameters& loop)
    : COutputLogger("slam"),
      orbParams_(orb),
      trackingParams_(resolveRevisitAge(tracking, loop)),
      mappingParams_(mapping),
      extractor_(std::make_unique<features::OrbExtractor>(orb)),
      map_(std::make_unique<Map>()),
      mapper_(std::make_unique<LocalMapper>(*map_, mapping)),
      loopCloser_(std::make_unique<LoopCloser>(*map_, *mapper_, loop, mapping)),
      tracker_(std::make_unique<Tracker>(*map_, *mapper_, trackingParams_))
{
    mapper_->setProcessedSink([this](const std::shared_ptr<KeyFrame>& kf)
                              { loopCloser_->insertKeyFrame(kf); });
}

RgbdSlam::~RgbdSlam()
{
    // The threads go first: they reference the map. Loop closing stops taking keyframes
    // before the mapper that hands them over goes, and goes last itself.
    tracker_.reset();
    loopCloser_->stop();
    mapper_.reset();
    loopCloser_.reset();
}

Frame RgbdSlam::prepare(const core::RgbdFrame& rgbd, const cv::Mat& fill_last) const
{
    Frame f;
    f.timestamp = rgbd.timestamp;
    f.camera = rgbd.camera;
    f.bf = trackingParams_.virtual_baseline * rgbd.camera.fx;
    f.closeDepth = trackingParams_.close_depth;
    f.features = extractor_->extract(rgbd.colour, fill_last);
    features::undistortKeypoints(f.features, rgbd.camera);
    features::assignDepth(
        f.features, rgbd.depth, f.bf, trackingParams_.min_depth, trackingParams_.max_depth,
        trackingParams_.depth_edge_ratio > 0.0 ? trackingParams_.depth_edge_ratio : 1e9);
    std::vector<int> levels;
    levels.reserve(f.size());
    for (const auto& kp : f.features.keypoints)
        levels.push_back(kp.octave);
    f.grid = features::FeatureGrid(f.features.undistorted, levels, rgbd.camera.width,
                                   rgbd.camera.height);
    f.weights.assign(f.size(), 1.0F);
    f.clearMatches();
    f.thumbnail = makeThumbnail(rgbd.colour);
    return f;
}

TrackingResult RgbdSlam::track(Frame frame)
{
    frame.id = nextFrameId_++;
    return tracker_->track(std::move(frame));
}

TrackingResult RgbdSlam::process(const core::RgbdFrame& rgbd, const cv::Mat& mask)
{
    const auto t0 = std::chrono::steady_clock::now();
    Frame f = prepare(rgbd);
    if (!mask.empty())
        f.setMask(mask);
    const double extraction =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    TrackingResult r = track(std::move(f));
    r.timings.extraction_ms = extraction;
    return r;
}

void RgbdSlam::setLoggingLevel(mrpt::system::VerbosityLevel level)
{
    setMinLoggingLevel(level);
    tracker_->setMinLoggingLevel(level);
    mapper_->setMinLoggingLevel(level);
    loopCloser_->setMinLoggingLevel(level);
}

void RgbdSlam::finish()
{
    mapper_->waitUntilIdle();
    loopCloser_->waitUntilIdle();
    tracker_->applyPendingMerge();
    discardUnmergedParts();
    if (finished_ || mappingParams_.global_ba_iterations <= 0)
        return;
    finished_ = true;
    const auto t0 = std::chrono::steady_clock::now();
    const std::atomic<bool> never{false};
    globalBa_ = globalBundleAdjustment(*map_, mappingParams_.global_ba_iterations,
                                       mappingParams_.ba_min_shared_observations, never);
    globalBaSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MRPT_LOG_INFO_FMT(
        "global bundle adjustment: %d keyframes (%d held, %d of them weakly tied), %d points, %d "
        "observations, %d outliers removed, %.2f s",
        globalBa_.keyframes, globalBa_.fixedKeyframes, globalBa_.weaklyTiedHeld, globalBa_.points,
        globalBa_.observations, globalBa_.outliersRemoved, globalBaSeconds_);
}

void RgbdSlam::discardUnmergedParts()
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    if (map_->liveParts().size() < 2)
        return;
    // The part that poses the most frames stays (the older one on a tie): its frame is the
    // world's. The others never met it again, so their poses rest on a prediction.
    std::map<uint32_t, size_t> posed;
    for (const auto& r : tracker_->records())
        if (hasPose(r.status) && r.reference)
            posed[r.reference->part()]++;
    uint32_t keep = *map_->liveParts().begin();
    for (const uint32_t part : map_->liveParts())
        if (posed[part] > posed[keep])
            keep = part;
    const std::set<uint32_t> parts = map_->liveParts();
    for (const uint32_t part : parts)
    {
        if (part == keep)
            continue;
        MRPT_LOG_WARN_FMT(
            "part %u of the map (%zu frames) never met part %u (%zu frames) again: "
            "its frames have no pose",
            part, posed[part], keep, posed[keep]);
        map_->discardPart(part);
    }
    const std::vector<uint64_t> dropped = tracker_->dropDiscardedPoses();
    discardedFrames_.insert(discardedFrames_.end(), dropped.begin(), dropped.end());
}

void RgbdSlam::forEachFramePose(
    const std::function<void(const Tracker::FrameRecord&, const mrpt::poses::CPose3D&)>& fn) const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    for (const auto& r : tracker_->records())
    {
        if (!hasPose(r.status) || !r.reference)
            continue;
        const Eigen::Isometry3d T_cam_world =
            r.T_cam_reference * r.reference->resolvedT_cam_world();
        fn(r, toCPose3D(T_cam_world.inverse()));
    }
}

core::Trajectory RgbdSlam::trajectory() const
{
    core::Trajectory out;
    forEachFramePose(
        [&](const Tracker::FrameRecord& r, const mrpt::poses::CPose3D& T_world_cam) {
            out.push_back({r.timestamp, T_world_cam});
        });
    return out;
}

std::map<uint64_t, mrpt::poses::CPose3D> RgbdSlam::framePoses() const
{
    std::map<uint64_t, mrpt::poses::CPose3D> out;
    forEachFramePose([&](const Tracker::FrameRecord& r, const mrpt::poses::CPose3D& T_world_cam)
                     { out.emplace(r.frameId, T_world_cam); });
    return out;
}

core::Trajectory RgbdSlam::keyFrameTrajectory() const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    core::Trajectory out;
    for (const auto& [id, kf] : map_->keyframes())
        if (!kf->isBad())
            out.push_back({kf->timestamp(), toCPose3D(kf->T_cam_world().inverse())});
    return out;
}

std::vector<Eigen::Vector3d> RgbdSlam::mapPointPositions() const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    std::vector<Eigen::Vector3d> out;
    for (const auto& [id, mp] : map_->points())
        if (!mp->isBad())
            out.push_back(mp->position_world);
    return out;
}

RgbdSlam::MapPartStats RgbdSlam::mapPartStats() const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    return {map_->partsStarted(), map_->partsMerged(), map_->partsDiscarded()};
}

size_t RgbdSlam::numKeyFrames() const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    return map_->keyframes().size();
}

size_t RgbdSlam::numPoints() const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    return map_->points().size();
}

size_t RgbdSlam::numPointsCreated() const
{
    std::lock_guard<std::mutex> lock(map_->mutex());
    return static_cast<size_t>(map_->pointsCreated());
}

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T)
{
    mrpt::math::CMatrixDouble44 M;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            M(r, c) = T.matrix()(r, c);
    return mrpt::poses::CPose3D(M);
}
}  // namespace smap::slam
