// Options of the semantic evidence in tracking ([semantic_evidence] section): how the movable
// classes that keyframe segmentation finds are carried to the frames after it and fused with the
// dynamic filter's flow evidence (docs/dynamic.md "Semantic evidence").
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

#include "smap/core/OptionFields.h"

namespace smap::dynamic
{
struct SemanticEvidenceParameters : public mrpt::config::CLoadableOptions
{
    /// Keypoints on a movable-class region (of the newest keyframe mask, warped into the frame)
    /// carry no weight and start no map points, moving or not. false: flow evidence only (A/B).
    /// Only with [dynamic] mode = strong: the paper's mode stays the paper's.
    bool enabled = true;
    /// Movable classes: dynamic prior (labels CSV) at least this (person 0.9).
    double movable_prior = 0.5;
    /// 0 (the default): each frame uses the newest mask that is ready and never waits for the
    /// segmentation; which mask that is depends on the threads' timing. T > 0 (s): a
    /// keyframe's mask is used by the frames at least T after the keyframe, and the first of
    /// them waits for a late segmentation, so that a run gives the same result every time
    /// ([pipeline] reproducible sets it when it is 0).
    double mask_latency_s = 0.0;
    /// A mask older than this (s) is not used.
    double max_mask_age_s = 2.0;
    /// The warped mask grows by dilation_px plus age_dilation_px_per_s per second of its age
    /// (people move while the mask ages), at most max_dilation_px.
    double dilation_px = 12.0;
    double age_dilation_px_per_s = 30.0;
    double max_dilation_px = 40.0;
    /// A keypoint in the grown mask, or labelled movable along its track, is movable only
    /// within this depth (m) of the nearest movable sample around it: the growth takes in a
    /// person, not the wall behind. Keypoints without depth: the mask alone decides.
    double depth_margin = 0.5;
    /// One 3-D sample of a mask every sample_step pixels (each way).
    int sample_step = 4;
    /// A keypoint the flow test found still is movable when it lies in the warped mask of the
    /// people who were clearly still on the keyframe, grown by this (px), even when its track
    /// carried a static label (labels handed on along tracks lose a person who sways).
    /// Negative: the label decides.
    double still_dilation_px = 6.0;
    /// A part of the keyframe mask is clearly still when at most this fraction of the keypoints
    /// the flow test measured on it on the keyframe moved.
    double still_part_max_moving = 0.34;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;

private:
    /// Every key of the section (default [semantic_evidence]), listed once.
    core::OptionFields fields(const std::string& section);
};
}  // namespace smap::dynamic
