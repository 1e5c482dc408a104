// The dynamic feature filter (METHOD.md section 2): per keypoint of the current frame, the
// residual optical flow after compensating the camera's own motion, and the decision
// "dynamic" that removes it from tracking (weight 0). Keeps the previous frame between calls.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
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
    bool dynamic = false;
    // The evidence behind `dynamic` (strong mode can have several; paper mode only `flow`).
    bool flow = false;    ///< residual > the frame's tau
    bool depth = false;   ///< measured in front of the warped previous surface
    bool region = false;  ///< most depth-similar neighbours are dynamic
};

struct DynamicResult
{
    std::vector<KeypointEvidence> keypoints;  ///< one per keypoint of the current frame
    /// False on the first frame of an active filter: with no previous frame there is no
    /// evidence either way, and weights() is then all 0 so that no map starts from a frame
    /// whose movers are unknown.
    bool evaluated = true;
    EgoMotion egoMotion;
    double tau = 0.0;                    ///< the threshold applied (px)
    double milliseconds = 0.0;           ///< total
    double egoMotionMilliseconds = 0.0;  ///< matching + five-point RANSAC + scale
    double warpMilliseconds = 0.0;
    double flowMilliseconds = 0.0;  ///< Lucas-Kanade

    /// Tracking weights: 0 for dynamic keypoints (all, when not evaluated), 1 otherwise.
    std::vector<float> weights() const;
    size_t numDynamic() const;
};

class DynamicFilter
{
public:
    explicit DynamicFilter(const DynamicParameters& params);

    /// Classifies the keypoints of a frame (colour BGR or grey, depth in metres, features
    /// with undistorted keypoints and depth) and remembers it as the previous frame. The first
    /// frame, and every frame in mode "off", has no dynamic keypoints.
    DynamicResult process(const cv::Mat& colour, const cv::Mat& depth,
                          const features::FeatureSet& features, const core::PinholeCamera& camera);
    void reset() { previousGrey_.release(); }

    const DynamicParameters& parameters() const { return params_; }

private:
    void decideStrong(const features::FeatureSet& features, const cv::Mat& warped_depth,
                      DynamicResult& result) const;

    DynamicParameters params_;
    cv::Mat previousGrey_;
    cv::Mat previousDepth_;
    features::FeatureSet previousFeatures_;
};
}  // namespace smap::dynamic
