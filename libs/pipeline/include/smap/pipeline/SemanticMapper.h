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

#include <memory>
#include <optional>

#include "smap/core/RgbdFrame.h"
#include "smap/core/Trajectory.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/mapping/SemanticMapBuilder.h"
#include "smap/pipeline/KeyFrameWorker.h"
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
    };

    PreparedFrame prepare(const core::RgbdFrame& frame);
    FrameResult track(PreparedFrame frame);
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
    SemanticMapperParameters params_;
    std::unique_ptr<slam::RgbdSlam> slam_;
    dynamic::DynamicFilter dynamicFilter_;
    std::unique_ptr<KeyFrameWorker> worker_;
    uint64_t keyframes_ = 0;
    mrpt::system::CTimeLogger profiler_;
};
}  // namespace smap::pipeline
