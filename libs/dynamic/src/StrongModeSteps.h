// The building blocks of the dynamic filter's strong mode (docs/method.md section 2, "beyond the
// paper"): depth hypotheses per keypoint, their prediction into the reference frame, the
// ego-motion refined on the Lucas-Kanade tracks, the residuals, and the decision (adaptive tau,
// isolated flow, region growing). Private to libs/dynamic.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/dynamic/DynamicParameters.h"
#include "smap/features/FeatureGrid.h"
#include "smap/features/FeatureSet.h"

namespace smap::dynamic::strong
{
/// A keypoint without depth takes the nearest and farthest valid depth within this many pixels.
constexpr int kDepthSearchRadius = 4;
/// Depth (m) that starts the flow when a frame has no keypoint depth at all.
constexpr float kNoDepthFallback = 2.0F;
/// Points nearer than this (m) to the reference camera's plane, or behind it, are not projected.
constexpr double kMinReferenceDepth = 0.05;
/// Depth range (m) a keypoint without any depth near it may have: its prediction is a segment.
constexpr double kUnknownNear = 0.3;
constexpr double kUnknownFar = 100.0;
/// Keypoints that were on movers stay out of the refinement and the adaptive tau only while at
/// least this many others remain.
constexpr size_t kMinWithoutMovers = 40;
/// Refinement of the ego-motion on the tracks: rounds, the fewest tracks worth a round, the most
/// used (a few hundred sub-pixel tracks fix the pose; more only cost time), and the first
/// round's "static" limit as a multiple of the median residual.
constexpr int kRefineRounds = 3;
constexpr size_t kMinRefineTracks = 20;
constexpr size_t kMaxRefineTracks = 200;
constexpr double kFirstRoundMedianFactor = 2.5;
/// The adaptive tau needs this many measured residuals; fewer: only the depth test decides.
constexpr size_t kMinResidualsForTau = 10;
/// MAD to standard deviation of a normal distribution.
constexpr double kMadToSigma = 1.4826;

/// Where each keypoint of the current frame may be in 3D (current camera frame).
struct DepthHypotheses
{
    std::vector<float> measured;         ///< the keypoint's own depth, 0 when none
    std::vector<cv::Point3f> nearPoint;  ///< at the nearest plausible depth
    std::vector<cv::Point3f> farPoint;   ///< at the farthest plausible depth
    std::vector<size_t> unknown;         ///< keypoints with no depth near (frame median used)
};
DepthHypotheses hypothesiseDepths(const features::FeatureSet& features, const cv::Mat& depth,
                                  const core::PinholeCamera& camera);

/// Where the keypoints were in the reference image (distorted pixels) under an ego-motion.
struct Prediction
{
    std::vector<cv::Point2f> pixels;     ///< under the near hypothesis
    std::vector<cv::Point2f> pixelsFar;  ///< under the far hypothesis
    std::vector<float> referenceDepth;   ///< z in the reference camera (near hypothesis)
};
Prediction predictInReference(const DepthHypotheses& hypotheses, const core::PinholeCamera& camera,
                              const Eigen::Isometry3d& T_cur_prev);

/// Lucas-Kanade from the current keypoints into the reference frame.
struct FlowTracks
{
    std::vector<cv::Point2f> tracked;
    std::vector<uint8_t> status;
    std::vector<float> error;
};

/// Lucas-Kanade from the current keypoints into the reference frame, started at `predicted`: a
/// static point is found at its prediction, a mover away from it.
FlowTracks trackIntoReference(const std::vector<cv::Mat>& currentPyramid,
                              const std::vector<cv::Mat>& referencePyramid,
                              const features::FeatureSet& features,
                              const std::vector<cv::Point2f>& predicted,
                              const DynamicParameters& params);

/// Keypoints that may refine the ego-motion: tracked, with depth, and not on a mover of the
/// reference frame (`wasDynamic`) unless too few others remain.
std::vector<bool> refinementCandidates(const DepthHypotheses& hypotheses, const FlowTracks& tracks,
                                       const std::vector<bool>& wasDynamic);

/// Refines the ego-motion on the sub-pixel tracks of the `usable` keypoints that look static
/// under the current estimate, in up to kRefineRounds rounds (the tracks do not depend on the
/// pose, so no second flow pass is needed); `prediction` follows the estimate.
void refineEgoMotionOnTracks(const DepthHypotheses& hypotheses, const FlowTracks& tracks,
                             const std::vector<bool>& usable, const core::PinholeCamera& camera,
                             const DynamicParameters& params, Eigen::Isometry3d& T_cur_prev,
                             Prediction& prediction);

/// The residual flow, depth and occlusion evidence of every keypoint, from its track and
/// prediction against the reference frame's depth.
void measureEvidence(const features::FeatureSet& features, const DepthHypotheses& hypotheses,
                     const Prediction& prediction, const FlowTracks& tracks,
                     const cv::Mat& referenceDepth, const core::PinholeCamera& camera,
                     const Eigen::Isometry3d& T_cur_prev, const DynamicParameters& params,
                     std::vector<KeypointEvidence>& evidence);

/// Adaptive tau from the frame's residuals; nullopt when too few were measured.
std::optional<double> adaptiveTau(const std::vector<KeypointEvidence>& evidence,
                                  const DynamicParameters& params);

/// Depth-similar neighbours of a keypoint within the region radius.
class NeighbourCounter
{
public:
    NeighbourCounter(const features::FeatureSet& features, const DynamicParameters& params);
    /// (neighbours, of them flagged in `flags`) of keypoint i, which must have depth.
    std::pair<int, int> count(size_t i, const std::vector<bool>& flags) const;
    const cv::Point2f& point(size_t i) const { return points_[i]; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    const features::FeatureSet& features_;
    const DynamicParameters& params_;
    std::vector<cv::Point2f> points_;
    int width_ = 1, height_ = 1;
    features::FeatureGrid grid_;
};

/// A keypoint flagged by its flow alone whose depth-similar neighbours are mostly static stays
/// static (a Lucas-Kanade slip on weak texture).
void overruleIsolatedFlow(const features::FeatureSet& features, const NeighbourCounter& neighbours,
                          const DynamicParameters& params, std::vector<KeypointEvidence>& evidence);

/// Region growing over depth-connected neighbours: two Jacobi sweeps (deterministic).
void growDynamicRegions(const features::FeatureSet& features, const NeighbourCounter& neighbours,
                        const DynamicParameters& params, std::vector<KeypointEvidence>& evidence);
}  // namespace smap::dynamic::strong
