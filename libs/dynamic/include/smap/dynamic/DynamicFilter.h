// The dynamic feature filter (docs/method.md section 2): per keypoint of the current frame, the
// residual optical flow after compensating the camera's own motion, and the decision
// "dynamic" that removes it from tracking (weight 0). Keeps the previous frame between calls.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/dynamic/DynamicParameters.h"
#include "smap/dynamic/EgoMotion.h"
#include "smap/features/FeatureSet.h"

namespace smap::dynamic
{
struct KeypointEvidence
{
    /// Residual flow (px) between the warped previous frame and the current frame at the
    /// keypoint; negative when Lucas-Kanade could not track it.
    float residual = -1.0F;
    /// Lucas-Kanade's mean absolute intensity difference over its window at the tracked
    /// position (grey levels; strong mode; negative when not tracked): high where the patch
    /// changed (occlusion, deformation).
    float patchError = -1.0F;
    bool dynamic = false;
    // The evidence behind `dynamic` (strong mode can have several; paper mode only `flow`).
    bool flow = false;    ///< residual > the frame's tau
    bool depth = false;   ///< measured in front of the warped previous surface
    bool region = false;  ///< most depth-similar neighbours are dynamic
    /// Flow said dynamic, but the depth-similar neighbours are mostly static: overruled.
    bool isolated = false;
    /// Temporal evidence (strong mode): where Lucas-Kanade found the keypoint in the reference
    /// frame, most of that frame's keypoints in the 3 x 3 cells of 8 px around were dynamic.
    /// Such keypoints neither refine the ego-motion nor set the adaptive tau; alone they
    /// decide nothing.
    bool wasDynamic = false;
    /// Semantic evidence (set by the pipeline after the filter): on a movable-class region of
    /// the newest keyframe segmentation warped into this frame. Makes the keypoint dynamic.
    bool semantic = false;
    /// Strong mode: where Lucas-Kanade found the keypoint in the reference frame (framesBack
    /// earlier; pixels); negative when it was not tracked. Semantic labels follow people
    /// along these tracks.
    cv::Point2f inReference{-1.0F, -1.0F};
};

struct DynamicResult
{
    std::vector<KeypointEvidence> keypoints;  ///< one per keypoint of the current frame
    /// False on the first frame of an active filter: with no previous frame there is no
    /// evidence either way, and weights() is then all 0 so that no map starts from a frame
    /// whose movers are unknown.
    bool evaluated = true;
    EgoMotion egoMotion;    ///< T_cur_prev: relative to the reference frame, framesBack earlier
    size_t framesBack = 0;  ///< how many frames back the reference was (0: not evaluated)
    double tau = 0.0;       ///< the threshold applied (px)
    double total_ms = 0.0;  ///< total
    double ego_motion_ms = 0.0;  ///< matching + five-point RANSAC + scale
    double warp_ms = 0.0;        ///< paper: the warp; strong: the image pyramid
    double flow_ms = 0.0;        ///< Lucas-Kanade

    /// Tracking weights: 0 for dynamic keypoints (all, when not evaluated), 1 otherwise.
    std::vector<float> weights() const;
    /// Which keypoints may start new map points: those judged static on a measured residual
    /// (a keypoint Lucas-Kanade lost has no evidence of being static, and lost tracks are
    /// far more common on people than on the background). Empty (all may) when no residual
    /// was measured at all (mode off, first frame, failed ego-motion).
    std::vector<bool> mappable() const;
    size_t numDynamic() const;
};

class DynamicFilter
{
public:
    explicit DynamicFilter(const DynamicParameters& params);
    ~DynamicFilter();
    DynamicFilter(DynamicFilter&&) noexcept;
    DynamicFilter& operator=(DynamicFilter&&) noexcept;

    /// Classifies the keypoints of a frame taken at `timestamp` (s, increasing; colour BGR or
    /// grey, depth in metres, features with undistorted keypoints and depth) and remembers it
    /// as the previous frame. The first frame, and every frame in mode "off", has no dynamic
    /// keypoints. The filter keeps `depth` for the next frames without copying it (cv::Mat
    /// shares the pixels): do not write into it afterwards.
    DynamicResult process(const cv::Mat& colour, const cv::Mat& depth,
                          const features::FeatureSet& features, const core::PinholeCamera& camera,
                          double timestamp);
    /// Strong mode, when more than extraction_priority_above of the last processed frame's
    /// keypoints were dynamic: where they were mostly dynamic, as a CV_8UC1 mask of 8 px
    /// cells (non-zero: a cell whose 5 x 5 neighbourhood held at least two keypoints, more
    /// than half of them dynamic), for the next frame's extraction (OrbExtractor's
    /// `fill_last`). Empty otherwise, and when no cell qualifies.
    cv::Mat moverRegions() const;
    /// Forgets the frames seen: the next frame is a first frame.
    void reset();

    const DynamicParameters& parameters() const { return params_; }

private:
    /// The frames kept for comparison and the two modes (PaperMode, StrongMode; private).
    struct State;

    /// Keeps the frame for the next ones (at most `keep`).
    void remember(const cv::Mat& grey, const cv::Mat& depth, const features::FeatureSet& features,
                  const DynamicResult& result, size_t keep, double timestamp);
    /// Strong mode: forgets the kept frames older than the newest one at least frame_gap_s
    /// before `timestamp`, which becomes the reference (the front).
    void dropFramesBeforeGap(double timestamp);
    /// Frames kept at most (strong mode), whatever the timestamps say.
    static constexpr size_t kMaxHistory = 30;

    DynamicParameters params_;
    std::unique_ptr<State> state_;
};
}  // namespace smap::dynamic
