// Table III-style scores of the keyframes of a run against ground-truth images, when the input
// has them (smap-synth's layout: GT/labels/<frame>.png with class ids, GT/dynamic/<frame>.png
// non-zero on moving pixels): the segmentation per class, and Algorithm 1's dynamic mask as
// one class "dynamic".
#pragma once

#include <mutex>
#include <optional>
#include <string>

#include "smap/core/JsonWriter.h"
#include "smap/core/LabelSet.h"
#include "smap/eval/SegmentationScore.h"
#include "smap/maps/CObservationSemanticRGBD.h"

namespace smap::apps
{
class KeyFrameScorer
{
public:
    /// `gtDirectory` holds labels/ and/or dynamic/. `scoreLabels`: whether the run segments.
    /// `voidLabel`: ground-truth label left out of the segmentation scores (-1: none is; e.g.
    /// composites whose labels are 255 "not person" away from the people).
    KeyFrameScorer(std::string gtDirectory, const core::LabelSet& labels, bool scoreLabels,
                   int voidLabel = 255);

    /// Scores one keyframe whose source name is `frameName`; frames without ground truth are
    /// counted as missing. Thread-safe.
    void add(const std::string& frameName, const maps::CObservationSemanticRGBD& obs);

    /// {"ground_truth": dir, "frames_scored", "frames_without_truth", "segmentation": {...},
    ///  "dynamic_mask": {...}}.
    core::JsonValue toJson() const;
    std::string toText() const;

    /// The ground-truth folder of an input, when it has one: a TUM-style folder that holds
    /// labels/ or dynamic/ itself (smap-synth's sequences), "<folder>/gt", or
    /// "<rawlog without extension>_gt" beside a rawlog; empty when none exists.
    static std::string findFor(const std::string& input);

private:
    std::string dir_;
    bool scoreLabels_;
    mutable std::mutex mutex_;
    std::optional<eval::SegmentationScore> segmentation_;
    eval::SegmentationScore dynamic_;
    size_t scored_ = 0;
    size_t missing_ = 0;
};
}  // namespace smap::apps
