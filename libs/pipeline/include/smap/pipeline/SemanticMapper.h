// The whole method on a stream of RGB-D frames, for the semantic-mapper app and for programs
// that embed it: features, the dynamic-feature filter, tracking and local BA, and keyframes
// handed to the segmentation + mapping worker (KeyFrameWorker), which fills the semantic maps.
//
// Frames go through prepare() (features and the dynamic filter: no map access) and track();
// the two may run on different threads (a front end and the tracker), each called in frame
// order. process() does both. finish() drains the worker and re-anchors the maps at the final
// keyframe poses.
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <mrpt/system/CTimeLogger.h>

#include <deque>
#include <memory>
#include <optional>
#include <utility>

#include "smap/core/RgbdFrame.h"
#include "smap/core/Trajectory.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/dynamic/MovableLabelTracker.h"
#include "smap/mapping/SemanticMapBuilder.h"
#include "smap/pipeline/KeyFrameWorker.h"
#include "smap/pipeline/MaskBoard.h"
#include "smap/pipeline/SemanticMapperParameters.h"
#include "smap/slam/RgbdSlam.h"

namespace smap::pipeline
{
class SemanticMapper : public mrpt::system::COutputLogger
{
public:
    /// Builds every part (loads the segmentation model: throws core::InputError when it is
    /// missing or wrong).
    explicit SemanticMapper(const SemanticMapperParameters& params);
    /// With a segmenter of the caller's own instead of the one [segmentation] describes (the
    /// label set still comes from there); null: no segmentation, every pixel void.
    SemanticMapper(const SemanticMapperParameters& params,
                   std::unique_ptr<segmentation::Segmenter> segmenter);
    ~SemanticMapper() override;
    SemanticMapper(const SemanticMapper&) = delete;
    SemanticMapper& operator=(const SemanticMapper&) = delete;

    /// A frame after the front end: features with depth, and the dynamic filter's verdicts.
    struct PreparedFrame
    {
        core::RgbdFrame rgbd;
        slam::Frame features;
        dynamic::DynamicResult dynamic;
        double extraction_ms = 0.0;
    };
    struct FrameResult
    {
        slam::TrackingResult tracking;
        size_t dynamicKeypoints = 0;
        double dynamic_ms = 0.0;
        bool keyframeDropped = false;  ///< a keyframe the full queue turned away (when_full = drop)
        double queue_wait_ms = 0.0;    ///< time tracking waited for room in the keyframe queue
        /// Semantic evidence: the age (frames) of the keyframe mask the frame used; nullopt
        /// when it used none (off, no keyframe segmented yet, or the newest too old).
        std::optional<uint64_t> maskAge;
        size_t movableKeypoints = 0;  ///< keypoints on the warped movable-class regions
        double mask_wait_ms = 0.0;    ///< time waiting for a late mask ([semantic_evidence])
        double semantic_ms = 0.0;     ///< semantic evidence, waiting included
    };

    PreparedFrame prepare(const core::RgbdFrame& frame);
    /// `inspect` (optional) sees the frame after the semantic evidence joined the filter's
    /// verdicts, before tracking (debug pictures).
    FrameResult track(PreparedFrame frame,
                      const std::function<void(const PreparedFrame&)>& inspect = nullptr);
    FrameResult process(const core::RgbdFrame& frame) { return track(prepare(frame)); }

    /// Minimum level logged by this object, tracking, local mapping and the worker.
    void setLoggingLevel(mrpt::system::VerbosityLevel level)
    {
        setMinLoggingLevel(level);
        slam_->setLoggingLevel(level);
        worker_->setMinLoggingLevel(level);
    }

    /// Called on the worker thread for each keyframe once it is in the maps (set before the
    /// first frame).
    void setKeyFrameObserver(KeyFrameWorker::Observer observer);

    /// Waits for local mapping and the worker, then re-anchors the maps at the final keyframe
    /// poses. Rethrows a failure of the worker.
    mapping::SemanticMapBuilder::ReanchorResult finish();

    core::Trajectory trajectory() const { return slam_->trajectory(); }
    core::Trajectory keyFrameTrajectory() const { return slam_->keyFrameTrajectory(); }
    const slam::RgbdSlam& slam() const { return *slam_; }
    KeyFrameWorker& worker() { return *worker_; }
    /// The maps; safe to call while frames are processed (locks the worker's maps).
    void withMaps(const std::function<void(mapping::SemanticMapBuilder&)>& fn)
    {
        worker_->withMaps(fn);
    }
    size_t keyframesSubmitted() const { return keyframes_; }
    /// Every stage's time (MRPT's profiler): per frame "frame.extraction", "frame.dynamic"
    /// (".ego_motion", ".warp", ".flow"), "frame.tracking" (".optimisation"), "frame.queue_wait";
    /// per keyframe, after finish(), "keyframe.segmentation", ".association", ".insertion",
    /// ".outputs".
    const mrpt::system::CTimeLogger& profiler() const { return profiler_; }
    const SemanticMapperParameters& parameters() const { return params_; }

private:
    /// [semantic_evidence] enabled, with the strong filter (the paper's mode and "off" use flow
    /// evidence only, or none).
    bool semanticEvidenceOn() const
    {
        return params_.semanticEvidence.enabled &&
               params_.dynamic.mode == dynamic::FilterMode::Strong;
    }
    /// Semantic evidence: flags the keypoints on movable-class regions of the newest usable
    /// keyframe mask as dynamic and movable (weight 0, no map points).
    void applySemanticEvidence(PreparedFrame& frame, FrameResult& r);
    /// Which keypoints are movable (dynamic::movableVerdicts): the label the tracker carried
    /// along their Lucas-Kanade track from the mask's keyframe, else the mask warped to the
    /// predicted pose; a still keypoint on a clearly still person of the mask even when its
    /// track carried a static label.
    std::vector<bool> movableKeypoints(const PreparedFrame& frame, const MaskBoard::MaskPtr& mask,
                                       double age_s);
    /// The recent frames' timestamps (tracker id, s), for mask latency and age in seconds.
    void rememberFrameTime(double timestamp);
    std::optional<uint64_t> newestFrameAtOrBefore(double timestamp) const;
    std::optional<double> frameTime(uint64_t frameId) const;
    /// s kept beyond the masks' largest age (label tracks, frame times).
    static constexpr double kLabelHistoryMargin_s = 0.15;
    /// A new mask: stillMask_ and clearlyStillMask_ from the flow test's verdicts on its
    /// keyframe.
    void keepStillParts(const MaskBoard::MaskPtr& mask);
    void markMovable(const std::vector<bool>& movable, PreparedFrame& frame, FrameResult& r);
    /// The frame's pose predicted at constant velocity from the last tracked ones.
    std::optional<Eigen::Isometry3d> predictPose(uint64_t frameId) const;
    /// S of Algorithm 1: the frame's keypoints that its dynamic filter calls dynamic.
    static std::vector<mapping::DynamicPoint> movingKeypoints(const PreparedFrame& frame);
    /// Announces a queued keyframe to the mask board.
    void submitKeyFrame(PreparedFrame& frame, std::vector<mapping::DynamicPoint> dynamicPoints,
                        FrameResult& r);

    SemanticMapperParameters params_;
    std::unique_ptr<slam::RgbdSlam> slam_;
    dynamic::DynamicFilter dynamicFilter_;
    MaskBoard maskBoard_;  ///< before worker_, which closes it when destroyed
    dynamic::MovableLabelTracker labelTracker_;
    std::optional<uint64_t> labelledMask_;  ///< keyframe of the mask the tracker has
    /// That mask without the people who were walking on its keyframe: the one warped by pose.
    std::shared_ptr<const dynamic::MovableMask> stillMask_;
    /// That mask with only the people who were clearly still on its keyframe (null: not used).
    std::shared_ptr<const dynamic::MovableMask> clearlyStillMask_;
    std::unique_ptr<KeyFrameWorker> worker_;
    uint64_t framesTracked_ = 0;  ///< = the tracker's id of the next frame
    /// The last tracked poses (tracker frame id, T_world_cam), newest last.
    std::deque<std::pair<uint64_t, Eigen::Isometry3d>> recentPoses_;
    std::deque<std::pair<uint64_t, double>> frameTimes_;  ///< oldest first
    /// `timestamp`, or the previous frame's plus 1/30 s when it is not after it (warned once).
    double increasingTimestamp(double timestamp);
    /// The front end's last frame time (s), for increasingTimestamp.
    std::optional<double> lastTimestamp_;
    bool timestampWarned_ = false;
    uint64_t keyframes_ = 0;
    mrpt::system::CTimeLogger profiler_;
};
}  // namespace smap::pipeline
