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
    Handheld,
    Loop  ///< around a rounded rectangle (LoopPath), looking ahead, with a hand-held sway
};

/// A closed path on a horizontal plane: the rectangle [min, max] with its corners rounded.
struct LoopPath
{
    Eigen::Vector2d min{0.0, 0.0}, max{1.0, 1.0};
    double cornerRadius = 0.5;  ///< m
    double height = 1.4;        ///< camera height, m
    double speed = 0.8;         ///< m/s along the path
    /// Length of one lap (m).
    double length() const;
    /// Point and unit heading at arc length s (any s: laps repeat), counter-clockwise from
    /// the middle of the lower edge.
    void at(double s, Eigen::Vector2d& point, Eigen::Vector2d& heading) const;
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
    /// CameraMotionKind::Loop along `path`.
    CameraMotion(const LoopPath& path, uint32_t seed);
    mrpt::poses::CPose3D T_world_cam(double t) const;
    CameraMotionKind kind() const { return kind_; }

private:
    mrpt::poses::CPose3D alongLoop(double t) const;
    double wave(int i, double amp, double t, double rate) const;

    CameraMotionKind kind_;
    LoopPath loop_;
    Eigen::Vector3d base_;
    Eigen::Vector3d target_;
    double phases_[9];
    double freqs_[9];
};
}  // namespace smap::sim
