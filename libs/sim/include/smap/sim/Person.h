// An articulated person: torso, head, two arms and two legs as textured boxes, walking along a
// closed path with swinging limbs, or sitting and gesturing.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <vector>

#include "smap/sim/SceneObject.h"

namespace smap::sim
{
struct PersonSpec
{
    enum class Kind
    {
        Walking,
        Sitting
    } kind = Kind::Walking;
    std::vector<Eigen::Vector2f> path;  ///< walking: closed polyline on the floor (x, y)
    Eigen::Vector2f seat{0, 0};         ///< sitting: position of the hips on the floor plane
    float seatHeight = 0.45f;           ///< sitting: hip height
    float facing = 0.0f;                ///< sitting: heading (rad, about z)
    float speed = 1.0f;                 ///< walking speed, m/s (0.5 - 1.5)
    float height = 1.75f;               ///< metres
    float phase = 0.0f;                 ///< s, start offset along the path / gesture cycle
};

class Person
{
public:
    /// Body parts share `instanceId` (one person = one instance) and class person.
    Person(const PersonSpec& spec, uint16_t instanceId, int shirtTexture, int trousersTexture,
           int skinTexture, uint32_t seed);

    /// Parts with quads in their own frames; poses come from partPoses().
    const std::vector<SceneObject>& parts() const { return parts_; }
    /// T_world_part of every part at time t (seconds), in parts() order.
    std::vector<mrpt::poses::CPose3D> partPoses(double t) const;
    /// Pose of the body frame (on the floor between the feet, x forward, z up) at time t.
    mrpt::poses::CPose3D rootPose(double t) const;
    const PersonSpec& spec() const { return spec_; }
    uint16_t instanceId() const { return instanceId_; }

private:
    PersonSpec spec_;
    uint16_t instanceId_;
    std::vector<SceneObject> parts_;
    double pathLength_ = 0.0;
};
}  // namespace smap::sim
