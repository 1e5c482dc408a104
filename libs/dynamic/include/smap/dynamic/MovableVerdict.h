// Which keypoints of a frame lie on a movable-class object (a person), from the two kinds of
// semantic evidence carried from the newest keyframe mask: the label each keypoint's track
// carried (MovableLabelTracker) and the mask warped into the frame by the camera pose
// (MovableMask::project), checked against what the flow test said of the keypoint.
#pragma once

#include <opencv2/core/types.hpp>
#include <vector>

#include "smap/dynamic/MovableLabelTracker.h"
#include "smap/dynamic/MovableMask.h"

namespace smap::dynamic
{
/// One frame's semantic evidence, per keypoint where a vector (same order as `pixels`).
struct MovableEvidence
{
    std::vector<cv::Point2f> pixels;  ///< undistorted keypoint positions
    std::vector<float> depth;         ///< m; <= 0: none
    std::vector<MovableLabelTracker::Label> labels;
    std::vector<MovableLabelTracker::Motion> motion;
    /// The mask of the people who were not walking on the keyframe, grown with its age.
    MovableCells grown;
    /// The mask of the people who were clearly still on the keyframe, barely grown (empty: not
    /// used).
    MovableCells still;
    float depthMargin = 0.5F;  ///< m (SemanticEvidenceParameters::depth_margin)
};

/// Per keypoint, whether it is movable:
/// - no label (Unknown): whether it lies inside `grown`;
/// - a static label on a keypoint the flow test found still: whether it lies inside `still`. A
///   person who stands still stays where the pose puts them, while the labels, handed on from
///   keypoint to keypoint every frame_gap_s by a majority of the still ones around, lose
///   a person who sways (their moving keypoints do not count);
/// - else its label.
std::vector<bool> movableVerdicts(const MovableEvidence& evidence);
}  // namespace smap::dynamic
