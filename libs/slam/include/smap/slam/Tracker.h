// Tracking: the pose of every frame against the map (ORB-SLAM2's RGB-D tracking). Constant
// velocity prediction with projection search, fallback to the reference keyframe, local map
// tracking over covisible keyframes, motion-only BA, keyframe decisions, relocalisation when
// lost. Knows nothing of semantics: outside knowledge arrives as per-keypoint weights.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <Eigen/Geometry>
#include <deque>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "smap/slam/Frame.h"
#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
class KeyFrame;
class LocalMapper;
class Map;
class MapPoint;

enum class TrackingStatus
{
    NotInitialised,  ///< waiting for a frame with enough depth
    Initialised,     ///< this frame started the map
    Ok,
    Relocalised,  ///< was lost, found again on this frame
    Reanchored,   ///< was lost too long: this frame re-anchored the map at its predicted pose
    Lost,
    /// Was tracked in a part of the map that re-anchoring started and that never met the rest
    /// again: the part was dropped at the end, and the frame's pose with it (only ever set on a
    /// record, after the fact).
    Discarded,
    /// Came before the map existed; posed afterwards from the outside odometry that links it to
    /// the frame that started the map (only ever set on a record, after the fact).
    Odometry
};
std::string toString(TrackingStatus s);

/// How a frame was tracked when the outside weights alone did not hold its pose ([tracking]
/// fallback_weight): each stage is tried only when the one before failed.
enum class TrackingFallback
{
    None,           ///< the outside weights held the pose, or no fallback did
    RaisedWeights,  ///< every keypoint outside movable regions weighted at least fallback_weight
    /// As RaisedWeights, plus the keypoints of movable regions that the motion evidence found
    /// still: where people fill the view a stale or grown mask can cover most of the background.
    StillMovable,
    /// The local map searched from the pose the outside odometry carried the frame to (the
    /// dynamic filter's ego-motion, chained over lost frames): where the motion model and the
    /// reference keyframe find too few matches, or after a loss ([tracking] carried_search_s).
    CarriedPose,
};
/// "", "raised_weights", "still_movable", "carried_pose" (frames.csv's fallback column).
std::string toString(TrackingFallback f);
inline bool hasPose(TrackingStatus s)
{
    return s == TrackingStatus::Initialised || s == TrackingStatus::Ok ||
           s == TrackingStatus::Relocalised || s == TrackingStatus::Reanchored ||
           s == TrackingStatus::Odometry;
}

struct TrackingTimings
{
    double extraction_ms = 0.0;
    double matching_ms = 0.0;  ///< total_ms less optimisation_ms and map_wait_ms
    double optimisation_ms = 0.0;
    double map_wait_ms = 0.0;  ///< waiting for the map mutex (held by local mapping or loops)
    double total_ms = 0.0;     ///< tracking alone (extraction excluded), wall time
    double cpu_ms = 0.0;       ///< CPU time of the tracking thread over total_ms
};

struct TrackingResult
{
    TrackingStatus status = TrackingStatus::NotInitialised;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< when hasPose(status)
    int inliers = 0;  ///< map point matches that survived the last pose optimisation
    int keypoints = 0;
    bool newKeyFrame = false;
    std::optional<uint64_t> keyFrameId;  ///< the new keyframe's id (KeyFrame::id())
    TrackingTimings timings;
    uint64_t frameId = 0;  ///< the tracker's running frame number (0 for the first frame)
    /// When this frame started the map: the earlier frame (not initialised when it came) that
    /// the outside odometry placed relative to it; its record now has status Odometry.
    std::optional<uint64_t> posedEarlierFrameId;
    /// Tracked only by a fallback ([tracking] fallback_weight): too few keypoints the outside
    /// judged static matched the map.
    TrackingFallback fallback = TrackingFallback::None;
};

class Tracker : public mrpt::system::COutputLogger
{
public:
    Tracker(Map& map, LocalMapper& mapper, const TrackerParameters& params);

    /// Tracks a prepared frame (features, depth, weights). Takes the frame: it becomes the
    /// "last frame" of the next call.
    TrackingResult track(Frame frame);

    /// One record per tracked frame, to rebuild the trajectory after keyframes are refined.
    struct FrameRecord
    {
        uint64_t frameId = 0;
        double timestamp = 0.0;
        TrackingStatus status = TrackingStatus::NotInitialised;
        std::shared_ptr<KeyFrame> reference;  ///< null when the frame has no pose
        Eigen::Isometry3d T_cam_reference = Eigen::Isometry3d::Identity();
    };
    const std::vector<FrameRecord>& records() const { return records_; }
    /// The merge of two parts of the map that the last frame found (probeOtherParts), with
    /// local mapping held still; tracking then follows it as it follows a loop correction.
    /// Each frame applies it first; finish() applies the last frame's. Takes the map mutex.
    void applyPendingMerge();
    /// After Map::discardPart: the frames posed in a discarded part lose their pose (status
    /// Discarded). Returns their frame numbers. Hold the map mutex.
    std::vector<uint64_t> dropDiscardedPoses();

private:
    /// Where the tracker stands between frames (ORB-SLAM's eTrackingState); the per-frame
    /// outcome is TrackingStatus.
    enum class TrackerState
    {
        NotInitialised,  ///< no map yet: each frame tries to start it
        Tracking,        ///< the last frame had a pose: motion model / reference keyframe
        Lost,            ///< relocalisation (or re-anchoring) until a frame is placed
    };
    /// One frame's attempt on the map: placed, and whether by relocalisation.
    struct Attempt
    {
        bool ok = false;
        bool relocalised = false;
        TrackingFallback fallback = TrackingFallback::None;  ///< the stage that succeeded
    };

    /// NotInitialised: the frame starts the map when it has enough depth.
    std::shared_ptr<KeyFrame> startMap(Frame& frame, TrackingResult& result);
    /// Tracking or Lost: the state's attempt, then re-anchoring, acceptance or loss.
    std::shared_ptr<KeyFrame> trackOnMap(Frame& frame, TrackingResult& result);
    Attempt trackWhileTracking(Frame& frame);
    Attempt trackWhileLost(Frame& frame);
    /// Lost for reanchor_after_s: a new keyframe at the carried or extrapolated pose.
    std::shared_ptr<KeyFrame> reanchor(Frame& frame,
                                       const std::optional<Eigen::Isometry3d>& carried,
                                       TrackingResult& result);
    std::shared_ptr<KeyFrame> acceptTracked(Frame& frame, bool relocalised, TrackingResult& result);
    void markLost(const Frame& frame, TrackingResult& result);
    void rememberPose(const Frame& frame, const TrackingResult& result,
                      const std::optional<Eigen::Isometry3d>& carried);
    void record(const Frame& frame, TrackingResult& result);

    bool initialise(Frame& frame);
    /// Projection search of the last frame's points at velocity x its pose, then pose-only BA.
    bool trackWithMotionModel(Frame& frame, const Eigen::Isometry3d& velocity);
    bool trackReferenceKeyFrame(Frame& frame);
    /// Descriptor matches with the reference keyframe's points, then pose-only BA from the
    /// guess; the inliers (0 with fewer than 15 consistent matches).
    int poseFromReferenceKeyFrame(Frame& frame, const Eigen::Isometry3d& T_cam_world_guess);
    /// When tracking failed with the outside weights: once more from the last frame with every
    /// weight raised to at least fallback_weight (0 disables), since the map points are
    /// static, keypoints the outside excluded by mistake can match them. Keypoints of movable
    /// regions stay out, unless `stage` is StillMovable and the motion evidence found them still
    /// (Frame::stillMovable). False when the stage would change no weight.
    bool trackWithRaisedWeights(Frame& frame, TrackingFallback stage);
    /// Whether a fallback stage's pose lies within fallback_max_jump(_deg) of the
    /// constant-velocity prediction (true without a velocity or with the check off).
    bool nearPrediction(const Frame& frame, TrackingFallback stage) const;
    bool relocalise(Frame& frame);
    /// The CarriedPose stage: the local map (of the loss, when lost) searched from the pose the
    /// outside odometry carried the frame to; false without such a pose, past
    /// carried_search_s of lost frames, or with too few inliers: min_inliers while tracking,
    /// carried_min_inliers for a lost frame.
    bool trackFromCarriedPose(Frame& frame);
    /// Adds `frame` as a keyframe at its current pose with points from its depth (the first
    /// keyframe, or a re-anchor, which starts a new part of the map: Map::newPart); false when
    /// it has fewer than `min_points` usable depths.
    bool anchorKeyFrame(Frame& frame, int min_points, bool newPart);
    /// While the map has other parts: relocalises a copy of the tracked frame among their
    /// keyframes; where it is placed, the two parts are to be merged (pendingMerge_), the newer
    /// into the older.
    void probeOtherParts(const Frame& frame);
    bool trackLocalMap(Frame& frame);
    void updateLocalMap(const Frame& frame);
    void collectLocalPoints(const Frame& frame);
    void joinRevisitedKeyFrames(const Frame& frame, std::set<uint64_t>& inLocal);
    bool tooOldForRevisit(const Frame& frame, const KeyFrame& kf) const;
    bool needNewKeyFrame(const Frame& frame) const;
    std::shared_ptr<KeyFrame> createKeyFrame(Frame& frame);
    void followReplacedPoints(Frame& frame) const;
    /// After a loop correction: the last poses move as the reference keyframe moved.
    void followLoopCorrection();
    int optimise(Frame& frame);

    Map& map_;
    LocalMapper& mapper_;
    TrackerParameters params_;
    TrackerState state_ = TrackerState::NotInitialised;
    std::optional<Frame> last_;
    std::optional<Eigen::Isometry3d> velocity_;  ///< T_cam_lastcam of the last step
    double velocityInterval_ = 0.0;              ///< s, the time velocity_ spans
    /// Re-anchoring: the last frame with a pose and its time, the velocity then (and the time
    /// it spans), frames lost since and the time of the first of them (s).
    std::optional<Eigen::Isometry3d> lastTracked_T_cam_world_;
    double lastTrackedTime_ = 0.0;
    std::optional<Eigen::Isometry3d> velocityAtLoss_;
    double velocityIntervalAtLoss_ = 0.0;
    int framesLost_ = 0;
    double lostSince_ = 0.0;
    /// T_cam_world of the last frames (tracked, or carried by outside odometry while lost).
    std::deque<std::pair<uint64_t, Eigen::Isometry3d>> recentPoses_;
    std::optional<Eigen::Isometry3d> odometryPose(const Frame& frame) const;
    /// `frame` just started the map: gives the earlier frame its outside odometry links it to
    /// (when that one has no pose yet) a pose relative to the new reference keyframe, the
    /// odometry's, refined against the map when that frame is the last one.
    std::optional<uint64_t> poseEarlierFrameFromOdometry(const Frame& frame);
    std::shared_ptr<KeyFrame> reference_;
    /// Two parts of the map that one frame placed in both: `from` moves into `to`'s frame.
    struct PartMerge
    {
        uint32_t from = 0, to = 0;
        Eigen::Isometry3d T_to_from = Eigen::Isometry3d::Identity();
        uint64_t frameId = 0;
        int inliers = 0;
    };
    std::optional<PartMerge> pendingMerge_;
    int partProbes_ = 0;  ///< probes so far: the relocalisation sweep's round
    /// The map's corrections, and the reference keyframe's pose, at the last frame.
    uint64_t correctionsSeen_ = 0;
    Eigen::Isometry3d T_reference_world_seen_ = Eigen::Isometry3d::Identity();
    double lastKeyFrameTime_ = 0.0;  ///< s, the newest keyframe's frame
    uint64_t lastRelocalisationFrameId_ = 0;
    double lastRelocalisationTime_ = 0.0;
    /// Within keyframe_max_interval_s of a relocalisation (ORB-SLAM's "mMaxFrames").
    bool recentlyRelocalised(const Frame& frame) const;
    /// Steps of the velocity at the loss that carry the last tracked pose to `frame`.
    int extrapolationSteps(const Frame& frame) const;
    std::vector<KeyFrame*> localKeyFrames_;
    /// Points of the local keyframes that the frame has not matched yet (the search's candidates).
    std::vector<std::shared_ptr<MapPoint>> localPoints_;
    uint64_t localSearch_ = 0;  ///< numbers each local-map search, for MapPoint::markForSearch
    std::vector<FrameRecord> records_;
    TrackingTimings timings_;
};
}  // namespace smap::slam
