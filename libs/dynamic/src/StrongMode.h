// The dynamic filter's strong mode (docs/method.md section 2, beyond the paper): depth-aided
// ego-motion against a frame frame_gap_s back, refined on the flow, predicted keypoints tracked
// with Lucas-Kanade, adaptive tau, depth and temporal evidence, region growing; its steps are
// in StrongModeSteps. Private to libs/dynamic.
#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "FrameHistory.h"
#include "smap/core/PinholeCamera.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/dynamic/DynamicParameters.h"

namespace smap::dynamic
{
class StrongMode
{
public:
    explicit StrongMode(const DynamicParameters& params) : params_(params) {}

    /// The frame's Lucas-Kanade pyramid (also the later frames' reference pyramid).
    void buildPyramid(const cv::Mat& grey);
    /// The evidence and decision of every keypoint of the current frame against the history's
    /// reference (its front).
    void evaluate(const cv::Mat& depth, const features::FeatureSet& features,
                  const core::PinholeCamera& camera, const FrameHistory& history,
                  const Stopwatch& lap, DynamicResult& result) const;
    /// After a frame: its ego-motion becomes the next prior (constant velocity), and `past`
    /// (the frame as the history keeps it) gets its pyramid and decisions.
    void remember(const DynamicResult& result, PastFrame& past);
    /// See DynamicFilter::moverRegions().
    cv::Mat moverRegions(const FrameHistory& history) const;
    void reset() { lastMotion_.reset(); }

private:
    EgoMotion estimateEgoMotion(const features::FeatureSet& features,
                                const core::PinholeCamera& camera,
                                const FrameHistory& history) const;
    /// Per current keypoint, whether the reference frame's keypoints around where it was there
    /// (its Lucas-Kanade track, else its prediction; within the 3 x 3 cells of 8 px) were
    /// mostly dynamic.
    static std::vector<bool> dynamicBefore(const PastFrame& reference,
                                           const std::vector<uint8_t>& status,
                                           const std::vector<cv::Point2f>& tracked,
                                           const std::vector<cv::Point2f>& predicted);
    void decide(const features::FeatureSet& features, DynamicResult& result) const;

    DynamicParameters params_;
    std::vector<cv::Mat> currentPyramid_;
    /// The last evaluated frame's ego-motion and how many frames back its reference was; the
    /// next frame with the same gap starts from it (constant velocity).
    std::optional<Eigen::Isometry3d> lastMotion_;
    size_t lastFramesBack_ = 0;
};
}  // namespace smap::dynamic
