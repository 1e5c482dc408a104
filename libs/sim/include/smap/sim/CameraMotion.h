// Camera motions modelled on the TUM fr3 sequences (static, xyz, rpy, halfsphere) plus a smooth
// hand-held random walk. Poses are T_world_cam of the optical frame (x right, y down, z forward)
// in the z-up world.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>

namespace smap::sim
{
enum class CameraMotionKind
{
    Static,
    Xyz,
    Rpy,
    Halfsphere,
    Handheld
};

CameraMotionKind parseCameraMotion(const std::string& name);  ///< throws core::InputError
std::string toString(CameraMotionKind k);

/// Optical-frame pose at `position` looking at `target`, with image "up" towards world +z.
mrpt::poses::CPose3D lookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target);

class CameraMotion
{
public:
    CameraMotion(CameraMotionKind kind, const Eigen::Vector3d& basePosition,
                 const Eigen::Vector3d& target, uint32_t seed);
    mrpt::poses::CPose3D T_world_cam(double t) const;
    CameraMotionKind kind() const { return kind_; }

private:
    CameraMotionKind kind_;
    Eigen::Vector3d base_;
    Eigen::Vector3d target_;
    double phases_[9];
    double freqs_[9];
};
}  // namespace smap::sim
