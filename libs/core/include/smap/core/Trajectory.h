// A camera trajectory: time-stamped poses of the camera's optical frame in the world frame.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <vector>

namespace smap::core
{
struct StampedPose
{
    double timestamp = 0.0;            ///< seconds
    mrpt::poses::CPose3D T_world_cam;  ///< maps points from the camera frame to the world
};

using Trajectory = std::vector<StampedPose>;
}  // namespace smap::core
