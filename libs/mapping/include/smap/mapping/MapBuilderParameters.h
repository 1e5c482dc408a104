// How keyframes become map content ([map], [points_map], [octomap] sections): which maps are
// filled, how a keyframe's static pixels are thinned, and when refined keyframe poses make the
// maps be rebuilt.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"

namespace smap::mapping
{
struct MapBuilderParameters : public mrpt::config::CLoadableOptions
{
    bool points_map = true;  ///< fill the CSemanticPointsMap
    bool octomap = true;     ///< fill the CSemanticOctoMap
    /// A keyframe's static pixels, back-projected in its camera frame, are thinned to one point
    /// per voxel of this edge (m) before insertion and kept as its contribution; 0 keeps all.
    double contribution_voxel = 0.02;
    /// After the run, when some keyframe's final (refined) pose differs from the pose it was
    /// inserted at by more than this translation (m) or rotation (deg), the maps are rebuilt
    /// from the stored contributions at the final poses.
    double reanchor_translation = 0.01;
    double reanchor_rotation_deg = 1.0;
    /// At the end of the run, with both maps filled: points-map points whose octomap voxel was
    /// carved free (occupancy below 0.5: later keyframes saw through it, e.g. where a person
    /// stood) are removed, as the octomap itself forgets them. Off by default: it also thins
    /// static surfaces seen at a glance (docs/mapping.md).
    bool prune_free_points = false;
    /// The same, only within this distance (m) of where a keyframe's dynamic pixels (M) were:
    /// what slipped past Algorithm 1 beside a person (a missed arm, the feet) goes once later
    /// keyframes see through it, and static surfaces elsewhere are not thinned. 0 = off.
    double prune_near_movers = 0.3;
    /// Confirmation near movers: at the end of the run, a keyframe's point within
    /// prune_near_movers of where movers were enters the maps only when at least this many
    /// keyframes put a point within about confirm_radius of it. A static surface beside a
    /// person is seen again from the next keyframes; a part of a walking person that
    /// segmentation and Algorithm 1 missed is somewhere else at each keyframe. The maps are
    /// rebuilt from the contributions without the unconfirmed points (only when there are
    /// some). 0 or 1 = off.
    int confirm_near_movers = 2;
    double confirm_radius = 0.05;  ///< m: the voxel of the test, which looks at 27 of them
    /// Time (s) the confirming keyframes must span at least (first to last): a person standing
    /// or walking slowly is at the same place in keyframes made shortly after one another.
    double confirm_span_s = 0.5;
    /// A confirmation also needs a keyframe to have put a point within confirm_radius of it
    /// with none of its own movers within about this distance (m; a voxel test over 27 voxels
    /// of this edge): a person who walks the same line again, or turns round, puts a part that
    /// segmentation missed at the same place in keyframes that all see them there; a static
    /// surface beside their path is also seen while they are elsewhere. 0: keyframes and span
    /// alone (A/B).
    double confirm_clear_distance = 0.2;
    /// Near movers, a point also leaves the maps when the newest keyframe that looked at its
    /// place saw a static surface more than this (m) behind it (a keyframe that saw a static
    /// surface in front of it is passed over): a person who stood there, or walked there and
    /// came back, has left, whatever earlier keyframes confirmed. 0 = off.
    double see_through_margin = 0.05;
    /// The see-through test also drops a point when, of the keyframes after the point's own
    /// that observed its place, at least one saw the static surface behind it and at least as
    /// many saw it behind as at it: a person who came back and stood in front of the place,
    /// missed by that keyframe's segmentation, does not bring back what an earlier walker left
    /// there. Off: the newest view alone decides.
    bool see_through_majority = true;
    /// A person who stands still is still a person: at the end of the run, a keyframe's point
    /// within this distance (m) of where keyframes made confirm_span_s or more apart saw
    /// the body of a movable-class object leaves the maps, though that keyframe's own
    /// segmentation missed the person (a back seen from behind, a head cut by the image's
    /// edge). A body is the pixels segmentation gave a class whose dynamic prior is at least
    /// movable_body_prior, more than movable_body_erosion pixels inside their region (not the
    /// outline, where labels spill onto the background), within 0.4 m of the region's median
    /// depth. 0 = off.
    double movable_body_radius = 0.04;
    int movable_body_erosion = 6;     ///< px
    double movable_body_prior = 0.5;  ///< above 1: no class

    /// [points_map] and [octomap]: the maps' own options (voxel size, resolution, sensor model,
    /// and the depth range / stride of back-projection, which the builder applies too).
    maps::CSemanticPointsMap::TInsertionOptions pointsMap;
    maps::CSemanticOctoMap::TInsertionOptions octoMap;

    /// The octomap here is fed the points-map's back-projected points (no stride of its own)
    /// and takes its class count from the label set: [octomap] has no stride or label_count.
    MapBuilderParameters() { octoMap.standalone_keys = false; }

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;

private:
    void loadMovableBody(const mrpt::config::CConfigFileBase& cfg);
};
}  // namespace smap::mapping
