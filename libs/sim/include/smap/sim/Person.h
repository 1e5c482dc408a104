// A person of the synthetic office: a real person cut-out (PersonSprite) drawn as a
// depth-consistent billboard (SpriteBillboard) facing the cameras' side of the room, either
// walking a closed path with a gait bob and sway, or sitting on a chair and swaying above the
// hips.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "smap/sim/SpriteBillboard.h"

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
    Eigen::Vector2f seat{0, 0};         ///< sitting: the chair seat's centre on the floor plane
    float seatHeight = 0.47f;           ///< sitting: hip height, the pivot of the sway
    Eigen::Vector2f viewer{0, 0};       ///< floor point the billboard faces (the cameras' side)
    float speed = 1.0f;                 ///< walking speed, m/s (0.5 - 1.5)
    float height = 1.75f;               ///< metres, floor to the top of the head (as drawn)
    float phase = 0.0f;                 ///< s, start offset along the path / sway cycle
    size_t sprite = 0;                  ///< index into the scene's person sprites
};

class Person
{
public:
    /// Throws std::invalid_argument for a walking person without a path.
    Person(const PersonSpec& spec, uint16_t instanceId);

    /// Pose of the body frame (on the floor, x forward, z up) at time t: along the path
    /// heading the way the person walks; on the seat facing the viewer.
    mrpt::poses::CPose3D rootPose(double t) const;
    /// Where the billboard stands at time t (seconds).
    BillboardPose billboard(double t) const;
    const PersonSpec& spec() const { return spec_; }
    uint16_t instanceId() const { return instanceId_; }

private:
    Eigen::Vector2d pointOnPath(double s) const;

    PersonSpec spec_;
    uint16_t instanceId_;
    double pathLength_ = 0.0;
};
}  // namespace smap::sim
