// Where keyframes saw the bodies of movable-class objects (people), as samples hashed by voxel:
// the test of [map] movable_body_radius (SemanticMapBuilder). Private to libs/mapping.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "smap/mapping/KeyFrameContribution.h"
#include "smap/maps/BackProjector.h"

namespace smap::mapping
{
class BodyVoxels
{
public:
    /// A keyframe's body samples (camera frame, one every 4 px): the pixels whose class is
    /// `movable`, more than `erosion` px inside their region (labels spill onto the background
    /// at outlines), with depth within kDepthSpan of their region's median depth (the
    /// background seen between an arm and the body, or between the legs, is not body).
    static std::vector<Eigen::Vector3f> samples(const maps::BackProjector::Images& images,
                                                const core::PinholeCamera& camera,
                                                const std::vector<bool>& movable, int erosion);
    /// m: how far from its region's median depth a body sample may lie (a person is at most
    /// about half a metre deep).
    static constexpr float kDepthSpan = 0.4F;

    /// `radius`: how near a body sample a point must lie (m); also the voxel edge. `span_s`:
    /// time (s) over which keyframes must have seen a body there (a person who stayed).
    BodyVoxels(double radius, double span_s);

    /// c's body samples at c's pose.
    void add(const KeyFrameContribution& c);
    /// Whether the world point p lies within the radius of body samples of keyframes made at
    /// least `span_s` apart: a person stayed there (a walking person's outline, where
    /// labels spill onto the background, is somewhere else a moment later).
    bool near(const Eigen::Vector3f& p) const;
    bool empty() const { return cells_.empty(); }

private:
    int64_t cell(float a) const;
    /// Marks voxel (cx, cy, cz) and its 26 neighbours in reach_.
    void addReach(int64_t cx, int64_t cy, int64_t cz);

    struct Sample
    {
        Eigen::Vector3f position;
        double time = 0.0;  ///< s, of the keyframe that saw it
    };
    double radius_;
    double span_s_;
    std::unordered_map<int64_t, std::vector<Sample>> cells_;
    /// The voxels with samples and their 26 neighbours: one lookup answers "none near" for
    /// most points.
    std::unordered_set<int64_t> reach_;
};
}  // namespace smap::mapping
