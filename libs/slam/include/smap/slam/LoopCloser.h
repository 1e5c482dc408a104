// Loop closing: every keyframe local mapping has processed is looked up among the places seen
// before (KeyFrameDatabase), a candidate is verified with depth (3D-3D RANSAC, then projection
// of its neighbourhood), and a verified loop is corrected: a pose graph over the keyframes
// (Ceres), map points moved with their keyframes, duplicates fused, then a global bundle
// adjustment. Runs in its own thread ([loop_closing] threaded) or, for deterministic runs,
// right after local mapping on its thread. Local mapping holds still during a correction;
// tracking goes on and re-expresses its last pose when it sees the map was corrected.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <Eigen/Geometry>
#include <memory>
#include <mutex>
#include <vector>

#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
class KeyFrame;
class KeyFrameQueue;
class LocalMapper;
class LoopDetector;
class Map;
struct LoopMatch;
struct PoseGraphEdge;

struct LoopClosure
{
    uint64_t keyFrameId = 0, loopKeyFrameId = 0;  ///< the new keyframe and the one it revisits
    uint64_t frameId = 0, loopFrameId = 0;        ///< their frame numbers
    double timestamp = 0.0, loopTimestamp = 0.0;
    int inliers = 0;           ///< 3D-3D RANSAC inliers
    int projectedMatches = 0;  ///< the loop neighbourhood's points found in the keyframe
    /// Measured T_cam_loop * T_cam_keyframe^-1 (the keyframe's camera into the loop's).
    Eigen::Isometry3d T_loop_keyframe = Eigen::Isometry3d::Identity();
    /// false: a consistent revisit (the loop agreed with the keyframe's pose within
    /// [loop_closing] min_correction_*): points fused, nothing moved.
    bool corrected = false;
    double correction_m = 0.0;    ///< how far the loop put the keyframe from where it was
    double correction_deg = 0.0;  ///< and turned it
    int keyframesCorrected = 0;
    int pointsFused = 0;
    double correctionSeconds = 0.0;  ///< detection done: pose graph, points, fusion
    double globalBaSeconds = 0.0;
};

struct LoopClosingStats
{
    size_t keyframesChecked = 0;
    size_t candidatesVerified = 0;
    size_t candidatesRejected = 0;
    std::vector<LoopClosure> closures;
};

class LoopCloser : public mrpt::system::COutputLogger
{
public:
    /// `mapping`: local mapping's `covisibility_min_weight`, for the edges re-counted after
    /// fusion, and `ba_min_shared_observations`, for the global BA after a correction.
    LoopCloser(Map& map, LocalMapper& mapper, const LoopClosingParameters& params,
               const LocalMappingParameters& mapping);
    ~LoopCloser() override;
    LoopCloser(const LoopCloser&) = delete;
    LoopCloser& operator=(const LoopCloser&) = delete;

    /// Queues a processed keyframe (threaded) or looks for a loop at once.
    void insertKeyFrame(const std::shared_ptr<KeyFrame>& kf);
    /// Blocks until every queued keyframe is checked (end of a run).
    void waitUntilIdle();
    /// Stops the thread; keyframes inserted afterwards are ignored (shutdown).
    void stop();
    LoopClosingStats stats() const;

private:
    void process(const std::shared_ptr<KeyFrame>& kf);
    /// With local mapping held still: corrects (or joins a consistent revisit), then the
    /// global bundle adjustment.
    void close(const std::shared_ptr<KeyFrame>& kf, const LoopMatch& match, LoopClosure& c);

    Map& map_;
    LocalMapper& mapper_;
    LoopClosingParameters params_;
    int covisibilityMinWeight_;
    int baMinSharedObservations_;
    std::unique_ptr<LoopDetector> detector_;
    std::vector<PoseGraphEdge> loopEdges_;

    mutable std::mutex statsMutex_;
    LoopClosingStats stats_;                // guarded by statsMutex_
    std::unique_ptr<KeyFrameQueue> queue_;  // last: its thread goes first
};
}  // namespace smap::slam
