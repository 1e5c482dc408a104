// What semantic-mapper records of every frame of a run: the frame's statistics and its tracking
// result, with the counts and per-frame timings metrics.json and frames.csv report.
#pragma once

#include <string>
#include <vector>

#include "smap/core/JsonWriter.h"
#include "smap/core/PinholeCamera.h"
#include "smap/io/FrameSource.h"
#include "smap/pipeline/FrameSummary.h"
#include "smap/pipeline/SemanticMapper.h"

namespace smap::apps
{
class RunLog
{
public:
    /// One frame's row. A result that started the map and posed an earlier frame from the
    /// outside odometry (TrackingResult::posedEarlierFrameId) turns that frame's status into
    /// `odometry`.
    void add(const pipeline::FrameStats& stats, double timestamp, const core::PinholeCamera& camera,
             const pipeline::SemanticMapper::FrameResult& result);

    /// A frame of the input that could not be read.
    void addSkipped(const io::SkippedFrame& frame);

    /// Frames read and processed (skipped ones not included).
    size_t frames() const { return rows_.size(); }
    size_t skipped() const { return skipped_.size(); }
    /// The first skipped frame (skipped() > 0).
    const io::SkippedFrame& firstSkipped() const { return skipped_.front(); }
    size_t withPose() const { return withPose_; }
    size_t lost() const { return lost_; }
    /// Frames whose pose went with a part of the map dropped at the end of the run
    /// (slam::RgbdSlam::discardedFrames): their status becomes `discarded`, without a pose.
    void markDiscarded(const std::vector<uint64_t>& frameIds);
    size_t discarded() const { return discarded_; }

    /// frames.csv: the frame statistics, then status, keypoints, inliers, keyframe, timings,
    /// and a note: every frame of the input in order, a skipped one with status `skipped`, no
    /// figures and the file and reason in its note. `timings` false: the timing columns empty
    /// (reproducible runs: they measure the machine).
    std::string framesCsv(bool timings) const;
    /// Sets "frames", "frames_skipped", "skipped" (the first 20: index, file, reason),
    /// "duration_s", "mean_valid_depth_fraction" and "camera" in `metrics`.
    void describeInput(core::JsonValue& metrics) const;
    /// frames_with_pose, frames_lost, frames_discarded, relocalisations, reanchors,
    /// frames_raised_weights,
    /// frames_still_movable, frames_carried_pose (the tracking fallbacks), frames_with_mask and
    /// median_mask_age (semantic evidence).
    core::JsonValue trackingJson() const;
    /// Sets feature_extraction, dynamic_filter, semantic_evidence, mask_wait, tracking and
    /// keyframe_queue_wait in `timings`.
    void addTimings(core::JsonValue& timings) const;
    /// Empty when at least half of the frames have a pose; otherwise how many do and the most
    /// likely reason read from the frames' statistics: (almost) no valid depth, a median depth
    /// outside the tracker's [minDepth, maxDepth] (a wrong depth factor), black images, or
    /// else too little texture or too fast a motion.
    std::string trackingDiagnosis(double minDepth, double maxDepth) const;

private:
    struct Row
    {
        pipeline::FrameStats stats;
        pipeline::SemanticMapper::FrameResult result;
    };
    std::vector<Row> rows_;
    std::vector<io::SkippedFrame> skipped_;
    size_t withPose_ = 0, lost_ = 0, relocalised_ = 0, reanchored_ = 0, discarded_ = 0;
    double firstStamp_ = 0.0, lastStamp_ = 0.0, sumValidDepth_ = 0.0;
    core::PinholeCamera camera_;
};

/// {"median_ms", "total_s", "count"} of a list of per-item milliseconds.
core::JsonValue timingJson(const std::vector<double>& milliseconds);
}  // namespace smap::apps
