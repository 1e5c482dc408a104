// The map: keyframes and map points, with the one mutex that guards all of them. Ids come from
// the map, so two maps (two pipelines) can live in one process.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>

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
    std::map<uint64_t, std::shared_ptr<KeyFrame>> keyframes_;
    std::map<uint64_t, std::shared_ptr<KeyFrame>> all_;
    std::map<uint64_t, std::shared_ptr<MapPoint>> points_;
};
}  // namespace smap::slam
