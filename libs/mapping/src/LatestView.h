// What the newest keyframe that looked at a place saw there: the test that drops what a person
// left where they stood or walked once a later keyframe sees the background through it
// (SemanticMapBuilder, [map] see_through_margin). Private to libs/mapping.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/mapping/KeyFrameContribution.h"
#include "smap/maps/BackProjector.h"

namespace smap::mapping
{
class LatestView
{
public:
    static constexpr int kCell = 8;  ///< pixels per cell edge
    /// A cell counts as observed when this share of its pixels has static depth.
    static constexpr double kObserved = 0.75;

    /// A keyframe's static depth per cell of kCell x kCell pixels (CV_32FC1): the nearest
    /// depth in [minDepth, maxDepth] of the pixels outside the dynamic mask, where at least
    /// kObserved of the cell's pixels have one; 0 elsewhere (not observed: no evidence).
    static cv::Mat staticDepthCells(const maps::BackProjector::Images& images, double minDepth,
                                    double maxDepth);

    /// The contributions' static depth cells (KeyFrameContribution::static_depth_cells, in
    /// keyframe order) at their current poses. `margin` (m): how far behind a point the
    /// surface a keyframe saw must lie for the point to count as seen through. `majority`:
    /// seenThrough also counts the views after the point's own keyframe.
    LatestView(const std::vector<KeyFrameContribution>& contributions, double margin,
               bool majority);

    /// Whether the place of the world point p, put there by contribution `own` (an index into
    /// the contributions), is empty now: the newest keyframe that observed the cell where p
    /// projects, and saw no static surface more than `margin` in front of p there (that one
    /// hides p: the keyframe before is asked), saw the surface more than `margin` behind p.
    /// With `majority`, also when at least one of the keyframes after `own` saw the surface
    /// behind p and at least as many saw it behind p as at p (a person who came back in front
    /// of the place, missed by the newest keyframe's segmentation, does not bring back what
    /// was seen through before).
    bool seenThrough(const Eigen::Vector3f& p_world, size_t own) const;

private:
    enum class Verdict
    {
        NoView,   ///< outside the image, behind the camera, or the cell not observed
        Hidden,   ///< a static surface in front of p
        Seen,     ///< the surface at p
        Through,  ///< the surface more than `margin` behind p
    };
    struct View
    {
        size_t contribution;  ///< index into the contributions
        Eigen::Isometry3f T_cam_world;
        core::PinholeCamera camera;
        cv::Mat cells;
    };

    Verdict look(const View& view, const Eigen::Vector3f& p_world) const;

    std::vector<View> views_;
    float margin_;
    bool majority_;
};
}  // namespace smap::mapping
