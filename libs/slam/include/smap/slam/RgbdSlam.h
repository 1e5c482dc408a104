// ORB-SLAM-style RGB-D SLAM: owns the map, the ORB extractor, tracking, local mapping (in its
// own thread unless [local_mapping] threaded = false) and loop closing (after local mapping).
// Frames are prepared (features, depth) and then tracked, so that a dynamic filter can weight the
// keypoints in between.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <functional>
#include <map>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/core/RgbdFrame.h"
#include "smap/core/Trajectory.h"
#include "smap/features/OrbParameters.h"
#include "smap/slam/BundleAdjustment.h"
#include "smap/slam/Frame.h"
#include "smap/slam/LocalMapper.h"
#include "smap/slam/LoopCloser.h"
#include "smap/slam/SlamParameters.h"
#include "smap/slam/Tracker.h"

namespace smap::features
{
class OrbExtractor;
}

namespace smap::slam
{
class Map;

class RgbdSlam : public mrpt::system::COutputLogger
{
public:
    RgbdSlam(const features::OrbParameters& orb, const TrackerParameters& tracking,
             const LocalMappingParameters& mapping, const LoopClosingParameters& loop = {});
    ~RgbdSlam() override;
    RgbdSlam(const RgbdSlam&) = delete;
    RgbdSlam& operator=(const RgbdSlam&) = delete;

    /// Features, undistorted keypoints, depth and the thumbnail of a frame (no map access).
    /// `fill_last`: see OrbExtractor::extract (regions whose corners are taken last).
    Frame prepare(const core::RgbdFrame& rgbd, const cv::Mat& fill_last = {}) const;
    /// Tracks a prepared frame; frame.weights (empty = all 1) carry the outside feature mask.
    TrackingResult track(Frame frame);
    /// prepare + track, with an optional CV_8UC1 mask (0 = do not use features there).
    TrackingResult process(const core::RgbdFrame& rgbd, const cv::Mat& mask = {});

    /// Minimum level logged by this object, tracking and local mapping.
    void setLoggingLevel(mrpt::system::VerbosityLevel level);

    /// Waits for local mapping to finish the queued keyframes, then runs the global bundle
    /// adjustment ([local_mapping] global_ba_iterations > 0). Call once, at the end of a run.
    void finish();
    /// What finish()'s global bundle adjustment did (all zero before finish() or when off).
    const BundleAdjustmentStats& globalBundleAdjustmentStats() const { return globalBa_; }
    double globalBundleAdjustmentSeconds() const { return globalBaSeconds_; }

    /// Pose of every frame that has one, through its reference keyframe's refined pose.
    core::Trajectory trajectory() const;
    /// T_world_cam of every frame with a pose, by the tracker's frame number (as trajectory()).
    std::map<uint64_t, mrpt::poses::CPose3D> framePoses() const;
    /// Current poses of the keyframes that were not culled.
    core::Trajectory keyFrameTrajectory() const;
    const std::vector<Tracker::FrameRecord>& records() const { return tracker_->records(); }

    /// World positions of the live map points.
    std::vector<Eigen::Vector3d> mapPointPositions() const;
    size_t numKeyFrames() const;
    size_t numPoints() const;
    /// Map points created so far, culled and fused ones included.
    size_t numPointsCreated() const;
    /// Parts of the map that re-anchoring started, and what became of them (Map::newPart).
    struct MapPartStats
    {
        uint32_t started = 0;
        uint32_t merged = 0;     ///< met another part again and joined it
        uint32_t discarded = 0;  ///< dropped at finish(), with their frames' poses
    };
    MapPartStats mapPartStats() const;
    /// The frames whose pose went with a discarded part (status Discarded), after finish().
    const std::vector<uint64_t>& discardedFrames() const { return discardedFrames_; }
    LocalMapper::Stats mappingStats() const { return mapper_->stats(); }
    LoopClosingStats loopClosingStats() const { return loopCloser_->stats(); }

private:
    /// At the end of a run: the parts of the map that re-anchoring started and no frame
    /// joined again (Map::mergePart) are dropped, all but the one that poses the most frames.
    void discardUnmergedParts();
    /// Every frame with a pose and its final T_world_cam (through the refined, possibly culled
    /// keyframes), in frame order, under the map lock.
    void forEachFramePose(const std::function<void(const Tracker::FrameRecord&,
                                                   const mrpt::poses::CPose3D&)>& fn) const;
    features::OrbParameters orbParams_;
    TrackerParameters trackingParams_;
    LocalMappingParameters mappingParams_;
    std::unique_ptr<features::OrbExtractor> extractor_;
    std::unique_ptr<Map> map_;
    std::unique_ptr<LocalMapper> mapper_;
    std::unique_ptr<LoopCloser> loopCloser_;
    std::unique_ptr<Tracker> tracker_;
    uint64_t nextFrameId_ = 0;
    bool finished_ = false;
    std::vector<uint64_t> discardedFrames_;
    BundleAdjustmentStats globalBa_;
    double globalBaSeconds_ = 0.0;
};

/// Optical-frame pose as an MRPT pose.
mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T);
}  // namespace smap::slam
