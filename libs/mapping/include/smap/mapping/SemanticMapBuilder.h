// The map insertion policy of semantic-mapper (docs/pipeline.md, "Refined keyframe poses"): every
// keyframe's static pixels are back-projected once, in the keyframe's camera frame, thinned to one
// point per voxel and kept as the keyframe's contribution; they are inserted into the semantic
// point map and the semantic octomap at the keyframe's pose of the moment. When bundle adjustment
// has refined keyframe poses, reanchor() compares the final poses with the insertion poses and, if
// any keyframe moved more than the tolerance, rebuilds both maps from the contributions at the
// final poses, in keyframe order: the final maps depend only on the final poses.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/mapping/KeyFrameContribution.h"
#include "smap/mapping/MapBuilderParameters.h"
#include "smap/maps/BackProjector.h"
#include "smap/maps/CSemanticOctoMap.h"
#include "smap/maps/CSemanticPointsMap.h"

namespace smap::mapping
{
class KeyFrameVoxels;

class SemanticMapBuilder
{
public:
    /// `labels` is the one source of class ids, colours and the octomap's class count.
    SemanticMapBuilder(const MapBuilderParameters& params, const core::LabelSet& labels);

    /// Adds keyframe number `keyframe` (ids increase with every call): back-projects the static
    /// pixels of `images` (dynamic mask skipped) in the camera frame, thins them, stores them and
    /// inserts them at T_world_cam. Returns the stored contribution.
    const KeyFrameContribution& add(uint64_t keyframe, uint64_t frameId, double timestamp,
                                    const maps::BackProjector::Images& images,
                                    const core::PinholeCamera& camera,
                                    const mrpt::poses::CPose3D& T_world_cam);

    struct ReanchorResult
    {
        size_t moved = 0;             ///< keyframes beyond the tolerance
        double maxTranslation = 0.0;  ///< m, over all keyframes
        double maxRotationDeg = 0.0;
        bool rebuilt = false;
        size_t pruned = 0;  ///< points-map points removed by pruneFreePoints() afterwards
        /// Contribution points near movers left out: unconfirmed, or confirmed but seen
        /// through by the newest keyframe that looked at their place (see_through_margin).
        size_t unconfirmed = 0;
        size_t seenThrough = 0;
        /// Contribution points left out near where a keyframe saw a person's body
        /// (movable_body_radius).
        size_t onBody = 0;
        size_t discarded = 0;  ///< contributions dropped (reanchor's `discard`)
    };
    /// `finalPose` gives each contribution's refined pose (nullopt: keep the insertion pose).
    /// The maps are rebuilt once when some keyframe moved beyond the tolerance or some point
    /// near movers is unconfirmed or seen through, or lies on a body a keyframe saw
    /// (dropUnconfirmedNearMovers, done here at the final poses). Contributions for which
    /// `discard` is true (a keyframe of a part of the SLAM map that was dropped, whose pose
    /// rests on a prediction) leave the maps first.
    ReanchorResult reanchor(
        const std::function<std::optional<mrpt::poses::CPose3D>(const KeyFrameContribution&)>&
            finalPose,
        const std::function<bool(const KeyFrameContribution&)>& discard = {});

    /// With both maps: removes the points-map points whose octomap voxel is known and free
    /// (occupancy < 0.5), all of them with prune_free_points, else those within
    /// prune_near_movers of where a keyframe's dynamic pixels were. Returns how many went.
    size_t pruneFreePoints();

    /// With prune_near_movers > 0 and confirm_near_movers >= 2 or see_through_margin > 0:
    /// rebuilds both maps from the contributions at their current poses without the points
    /// near movers that fewer than confirm_near_movers keyframes confirm, or that the newest
    /// keyframe looking at their place saw through; with movable_body_radius > 0 also without
    /// those on a body some keyframe saw (MapBuilderParameters). Returns how many
    /// contribution points were left out; the maps stay as they are when none is.
    size_t dropUnconfirmedNearMovers();

    const maps::CSemanticPointsMap& pointsMap() const { return pointsMap_; }
    const maps::CSemanticOctoMap& octoMap() const { return octoMap_; }
    const std::vector<KeyFrameContribution>& contributions() const { return contributions_; }
    /// Bytes held by the stored contributions.
    size_t contributionBytes() const;
    const MapBuilderParameters& parameters() const { return params_; }

private:
    /// Per contribution, per point of points_cam: whether it enters the maps.
    using KeepMasks = std::vector<std::vector<bool>>;
    /// Inserts c at its pose; `keep` (when set, one entry per point) picks which of its points.
    void insert(const KeyFrameContribution& c, const std::vector<bool>* keep = nullptr);
    /// Clears both maps and inserts every contribution at its pose, filtered by `keep` (null:
    /// all points).
    void rebuild(const KeepMasks* keep);
    struct NearMoverDrops
    {
        size_t unconfirmed = 0;
        size_t seenThrough = 0;  ///< confirmed, but seen through since
        size_t onBody = 0;       ///< near where a keyframe saw a movable-class body
    };
    /// The test of dropUnconfirmedNearMovers at the contributions' poses, decided once per
    /// point: nullopt when off or when it would drop nothing; `dropped` says how many
    /// contribution points it drops.
    std::optional<KeepMasks> nearMoverFilter(NearMoverDrops& dropped) const;
    /// Per world point and the index of the contribution that put it: whether the end-of-run
    /// tests drop it (counted in `dropped`): on a movable-class body seen by a keyframe
    /// (`bodyTest`), else near movers and unconfirmed (`confirm`) or seen through
    /// (`seeThrough`). `world`: each contribution at its pose.
    std::function<bool(const Eigen::Vector3f&, size_t, NearMoverDrops&)> dropTest(
        const std::vector<std::vector<maps::SemanticPoint>>& world, bool confirm, bool seeThrough,
        bool bodyTest) const;
    /// Which keyframes put the points near movers (world: each contribution at its pose).
    std::shared_ptr<const KeyFrameVoxels> confirmationVoxels(
        const std::vector<std::vector<maps::SemanticPoint>>& world,
        const std::function<bool(const Eigen::Vector3f&)>& near) const;
    /// c's points in the world frame, at c's pose.
    static std::vector<maps::SemanticPoint> toWorld(const KeyFrameContribution& c);
    /// Samples of the dynamic pixels with depth (every 4 px), in the camera frame.
    static std::vector<Eigen::Vector3f> moverSamples(const maps::BackProjector::Images& images,
                                                     const core::PinholeCamera& camera);
    /// Whether a world point lies within prune_near_movers of a mover sample (voxel test).
    std::function<bool(const Eigen::Vector3f&)> nearMovers() const;

    MapBuilderParameters params_;
    maps::BackProjector projector_;
    std::vector<bool> movable_;  ///< per class id: movable_body_prior or more
    maps::CSemanticPointsMap pointsMap_;
    maps::CSemanticOctoMap octoMap_;
    std::vector<KeyFrameContribution> contributions_;
};
}  // namespace smap::mapping
