// The map: keyframes and map points, with the one mutex that guards all of them. Ids come from
// the map, so two maps (two pipelines) can live in one process.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "smap/slam/KeyFrame.h"
#include "smap/slam/MapPoint.h"

namespace smap::slam
{
class Map
{
public:
    /// Held by tracking while it reads the map and by local mapping while it changes it;
    /// bundle adjustment solves without it.
    std::mutex& mutex() { return mutex_; }

    /// Tracking's place in front of background work done in short steps: a std::mutex is not
    /// fair, and a thread that unlocks and locks again at once (a revisit's fusion, one
    /// keyframe a step) would keep tracking waiting for all its steps. Tracking counts itself
    /// in while it waits for mutex(); such work waits for trackingWaits() to be false before
    /// each step.
    void beginTrackingWait() { trackingWaiting_.fetch_add(1); }
    void endTrackingWait() { trackingWaiting_.fetch_sub(1); }
    bool trackingWaits() const { return trackingWaiting_.load() > 0; }

    std::shared_ptr<KeyFrame> createKeyFrame(const Frame& frame);
    std::shared_ptr<MapPoint> createPoint(const Eigen::Vector3d& position_world,
                                          KeyFrame* reference);

    /// Live (not bad) keyframes and points by id.
    const std::map<uint64_t, std::shared_ptr<KeyFrame>>& keyframes() const { return keyframes_; }
    const std::map<uint64_t, std::shared_ptr<MapPoint>>& points() const { return points_; }
    /// Every keyframe ever created, culled ones included (for the trajectory).
    const std::map<uint64_t, std::shared_ptr<KeyFrame>>& allKeyFrames() const { return all_; }

    /// Points created so far, culled and fused ones included.
    uint64_t pointsCreated() const { return nextPointId_; }

    /// Drops bad keyframes and points from the live sets.
    void removeBad();

    /// Parts of the map (KeyFrame::part): a re-anchored tracker starts a new part in the same
    /// map, in a frame of its own (its first keyframe at the pose the tracker predicted), and
    /// a relocalisation of one of its frames against another part joins them.
    uint32_t newPart();
    /// Parts holding keyframes that are neither merged nor discarded (0 always, once started).
    const std::set<uint32_t>& liveParts() const { return liveParts_; }
    /// Moves every keyframe (culled ones included) and point of part `from` into the frame of
    /// part `to` and makes them part `to`. T_to_from maps a point of `from`'s frame into
    /// `to`'s. Hold the map mutex, with local mapping held still (LocalMapper::processingMutex):
    /// a bundle adjustment solved before would write back the old poses.
    void mergePart(uint32_t from, uint32_t to, const Eigen::Isometry3d& T_to_from);
    /// Culls every keyframe of `part` and the points only they observe; its frames have no pose
    /// (isDiscarded). Hold the map mutex, with local mapping idle.
    void discardPart(uint32_t part);
    bool isDiscarded(uint32_t part) const { return discarded_.count(part) > 0; }
    /// Parts started by re-anchoring, merged into another part, and discarded, so far.
    uint32_t partsStarted() const { return nextPart_ - 1; }
    uint32_t partsMerged() const { return merged_; }
    uint32_t partsDiscarded() const { return static_cast<uint32_t>(discarded_.size()); }
    /// Corrections (loop closures, global bundle adjustments) applied so far: tracking
    /// re-expresses its last poses when it changes.
    uint64_t corrections() const { return corrections_; }
    void noteCorrection() { ++corrections_; }

private:
    std::mutex mutex_;
    std::atomic<int> trackingWaiting_{0};
    uint64_t nextKeyFrameId_ = 0;
    uint64_t nextPointId_ = 0;
    uint64_t corrections_ = 0;
    uint32_t nextPart_ = 1;
    std::set<uint32_t> liveParts_ = {0};
    std::set<uint32_t> discarded_;
    uint32_t merged_ = 0;
    std::map<uint64_t, std::shared_ptr<KeyFrame>> keyframes_;
    std::map<uint64_t, std::shared_ptr<KeyFrame>> all_;
    std::map<uint64_t, std::shared_ptr<MapPoint>> points_;
};
}  // namespace smap::slam
