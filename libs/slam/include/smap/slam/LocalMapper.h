// Local mapping: takes the keyframes tracking inserts, links their points into the map, culls
// weak points, starts points that a covisible keyframe sees too, fuses duplicates with covisible
// keyframes, runs local bundle adjustment and culls
// redundant keyframes. Runs in its own thread (tracking never waits for it) or, for tests and
// reproducible runs, synchronously.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <atomic>
#include <functional>
#include <list>
#include <memory>
#include <mutex>

#include "smap/slam/BundleAdjustment.h"
#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
class KeyFrame;
class KeyFrameQueue;
class Map;
class MapPoint;

class LocalMapper : public mrpt::system::COutputLogger
{
public:
    LocalMapper(Map& map, const LocalMappingParameters& params);
    ~LocalMapper() override;
    LocalMapper(const LocalMapper&) = delete;
    LocalMapper& operator=(const LocalMapper&) = delete;

    /// Queues a keyframe. Synchronous mode processes it before returning.
    void insertKeyFrame(const std::shared_ptr<KeyFrame>& kf);
    /// True when nothing is queued or being processed.
    bool idle() const;
    size_t queued() const;
    /// Asks a running bundle adjustment to stop early.
    void interruptBundleAdjustment() { abortBa_ = true; }
    /// Blocks until every queued keyframe is processed (end of a run).
    void waitUntilIdle();

    /// Called with each keyframe once it is processed (loop closing), on local mapping's thread.
    void setProcessedSink(std::function<void(const std::shared_ptr<KeyFrame>&)> sink)
    {
        sink_ = std::move(sink);
    }
    /// Held while a keyframe is processed: loop correction holds it to keep local mapping still.
    std::mutex& processingMutex() { return processing_; }
    /// True while a keyframe waits for processingMutex() (a loop correction's bundle adjustment
    /// stops early then).
    const std::atomic<bool>& keyFrameWaiting() const { return waiting_; }

    struct Stats
    {
        size_t keyframesProcessed = 0;
        size_t keyframesCulled = 0;
        size_t pointsCulled = 0;
        size_t pointsFused = 0;
        size_t pointsFromNeighbours = 0;
        size_t baRuns = 0;
        size_t baAborted = 0;
        size_t baWeaklyTiedHeld = 0;  ///< keyframes held over all runs (BundleAdjustment.h)
        double baSeconds = 0.0;
        double totalSeconds = 0.0;
    };
    Stats stats() const;

private:
    void process(const std::shared_ptr<KeyFrame>& kf);
    void processHeld(const std::shared_ptr<KeyFrame>& kf);
    void linkNewKeyFrame(const std::shared_ptr<KeyFrame>& kf);
    void cullRecentPoints(const KeyFrame& kf);
    void createPointsWithNeighbours(const std::shared_ptr<KeyFrame>& kf);
    void fuseWithNeighbours(const std::shared_ptr<KeyFrame>& kf);
    void cullKeyFrames(const KeyFrame& kf);

    Map& map_;
    LocalMappingParameters params_;
    std::list<std::shared_ptr<MapPoint>> recentPoints_;

    mutable std::mutex statsMutex_;
    std::atomic<bool> abortBa_{false};
    Stats stats_;    // guarded by statsMutex_
    Stats pending_;  // counted by the worker under the map mutex, merged into stats_
    std::function<void(const std::shared_ptr<KeyFrame>&)> sink_;
    std::mutex processing_;
    std::atomic<bool> waiting_{false};
    std::unique_ptr<KeyFrameQueue> queue_;  // last: its thread goes first
};
}  // namespace smap::slam
