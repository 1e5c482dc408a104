#include "smap/sim/CameraMotion.h"

#include <mrpt/core/format.h>
#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "smap/core/InputError.h"

namespace smap::sim
{
CameraMotionKind parseCameraMotion(const std::string& name)
{
    if (name == "static")
        return CameraMotionKind::Static;
    if (name == "xyz")
        return CameraMotionKind::Xyz;
    if (name == "rpy")
        return CameraMotionKind::Rpy;
    if (name == "halfsphere")
        return CameraMotionKind::Halfsphere;
    if (name == "handheld")
        return CameraMotionKind::Handheld;
    if (name == "loop")
        return CameraMotionKind::Loop;
    throw core::InputError(mrpt::format(
        "camera motion '%s' is not one of static, xyz, rpy, halfsphere, handheld, loop",
        name.c_str()));
}

std::string toString(CameraMotionKind k)
{
    switch (k)
    {
        case CameraMotionKind::Static:
            return "static";
        case CameraMotionKind::Xyz:
            return "xyz";
        case CameraMotionKind::Rpy:
            return "rpy";
        case CameraMotionKind::Halfsphere:
            return "halfsphere";
        case CameraMotionKind::Handheld:
            return "handheld";
        case CameraMotionKind::Loop:
            return "loop";
    }
    return "?";
}

mrpt::poses::CPose3D lookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target)
{
    const Eigen::Vector3d z = (target - position).normalized();
    Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
    if (x.norm() < 1e-9)
        x = Eigen::Vector3d::UnitX();  // looking straight up or down
    x.normalize();
    const Eigen::Vector3d y = z.cross(x);
    mrpt::math::CMatrixDouble33 R;
    for (int r = 0; r < 3; r++)
    {
        R(r, 0) = x[r];
        R(r, 1) = y[r];
        R(r, 2) = z[r];
    }
    mrpt::math::CVectorFixedDouble<3> t;
    t[0] = position.x();
    t[1] = position.y();
    t[2] = position.z();
    return mrpt::poses::CPose3D(R, t);
}

double LoopPath::length() const
{
    const Eigen::Vector2d e = max - min;
    return 2.0 * (e.x() + e.y()) - 8.0 * cornerRadius + 2.0 * M_PI * cornerRadius;
}

void LoopPath::at(double s, Eigen::Vector2d& point, Eigen::Vector2d& heading) const
{
    const double r = cornerRadius;
    const Eigen::Vector2d e = max - min;
    // Straight edges (counter-clockwise: bottom, right, top, left) and quarter arcs between.
    const double straight[4] = {e.x() - 2 * r, e.y() - 2 * r, e.x() - 2 * r, e.y() - 2 * r};
    const Eigen::Vector2d starts[4] = {{min.x() + r, min.y()},
                                       {max.x(), min.y() + r},
                                       {max.x() - r, max.y()},
                                       {min.x(), max.y() - r}};
    const Eigen::Vector2d dirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const double arc = 0.5 * M_PI * r;
    double u = std::fmod(s + 0.5 * straight[0], length());
    if (u < 0)
        u += length();
    for (int k = 0; k < 4; ++k)
    {
        if (u <= straight[k])
        {
            point = starts[k] + u * dirs[k];
            heading = dirs[k];
            return;
        }
        u -= straight[k];
        if (u <= arc || k == 3)
        {
            const double a = std::min(u, arc) / r;                // turned so far, radians
            const Eigen::Vector2d d = dirs[k], n(-d.y(), d.x());  // n: towards the centre
            const Eigen::Vector2d centre = starts[k] + straight[k] * d + r * n;
            point = centre - r * (std::cos(a) * n) + r * std::sin(a) * d;
            heading = std::cos(a) * d + std::sin(a) * n;
            return;
        }
        u -= arc;
    }
}

CameraMotion::CameraMotion(const LoopPath& path, uint32_t seed)
    : CameraMotion(CameraMotionKind::Loop, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), seed)
{
    loop_ = path;
}

double CameraMotion::wave(int i, double amp, double t, double rate) const
{
    return amp * std::sin(2.0 * M_PI * rate * freqs_[i] * t + phases_[i]);
}

mrpt::poses::CPose3D CameraMotion::alongLoop(double t) const
{
    Eigen::Vector2d p, h;
    loop_.at(loop_.speed * t, p, h);
    // Hand-held: the camera sways sideways and up and down, and looks about the way ahead.
    const Eigen::Vector2d side(-h.y(), h.x());
    const Eigen::Vector3d position(p.x() + wave(0, 0.08, t, 0.3) * side.x(),
                                   p.y() + wave(0, 0.08, t, 0.3) * side.y(),
                                   loop_.height + wave(1, 0.05, t, 0.4));
    const double yaw = wave(2, 0.25, t, 0.2), pitch = -0.12 + wave(3, 0.08, t, 0.25);
    const Eigen::Vector2d look2 = std::cos(yaw) * h + std::sin(yaw) * side;
    const Eigen::Vector3d look(look2.x(), look2.y(), std::tan(pitch));
    return lookAt(position, position + look) +
           mrpt::poses::CPose3D(0, 0, 0, wave(4, 0.05, t, 0.3), 0, 0);
}

CameraMotion::CameraMotion(CameraMotionKind kind, const Eigen::Vector3d& basePosition,
                           const Eigen::Vector3d& target, uint32_t seed)
    : kind_(kind), base_(basePosition), target_(target)
{
    std::mt19937 rng(seed ^ 0xC0FFEEu);
    std::uniform_real_distribution<double> ph(0.0, 2.0 * M_PI), fr(0.6, 1.4);
    for (int i = 0; i < 9; i++)
    {
        phases_[i] = ph(rng);
        freqs_[i] = fr(rng);
    }
}

mrpt::poses::CPose3D CameraMotion::T_world_cam(double t) const
{
    mrpt::poses::CPose3D base = lookAt(base_, target_);
    switch (kind_)
    {
        case CameraMotionKind::Static:
            return base;
        case CameraMotionKind::Xyz:
        {
            // Translation along the camera's own axes, orientation fixed (as fr3 *_xyz).
            const double w = 2.0 * M_PI / 6.0;
            const mrpt::poses::CPose3D d(0.25 * std::sin(w * t), 0.15 * std::sin(1.3 * w * t + 1.0),
                                         0.2 * std::sin(0.7 * w * t + 2.0), 0, 0, 0);
            return base + d;
        }
        case CameraMotionKind::Rpy:
        {
            const double w = 2.0 * M_PI / 5.0;
            // Camera-frame rotation: yaw about optical z (roll of the image), then pitch/pan.
            const mrpt::poses::CPose3D d(0, 0, 0, 0.25 * std::sin(w * t),
                                         0.3 * std::sin(0.8 * w * t + 1.0),
                                         0.2 * std::sin(1.2 * w * t + 2.0));
            return base + d;
        }
        case CameraMotionKind::Halfsphere:
        {
            // On a sphere of radius 0.6 m around the base position, always facing the target.
            const double w = 2.0 * M_PI / 8.0;
            const double az = 1.2 * std::sin(w * t), el = 0.5 * std::sin(1.7 * w * t);
            const Eigen::Vector3d back = (base_ - target_).normalized();
            const Eigen::Vector3d side = back.cross(Eigen::Vector3d::UnitZ()).normalized();
            const Eigen::Vector3d up = side.cross(back);
            const Eigen::Vector3d offset =
                0.6 * (std::sin(az) * std::cos(el) * side + std::sin(el) * up);
            return lookAt(base_ + offset, target_);
        }
        case CameraMotionKind::Handheld:
        {
            const double rate = 0.15;
            const Eigen::Vector3d p =
                base_ + Eigen::Vector3d(wave(0, 0.4, t, rate), wave(1, 0.3, t, rate),
                                        wave(2, 0.15, t, rate));
            const Eigen::Vector3d look =
                target_ + Eigen::Vector3d(wave(3, 0.6, t, rate), wave(4, 0.4, t, rate),
                                          wave(5, 0.3, t, rate));
            return lookAt(p, look) + mrpt::poses::CPose3D(0, 0, 0, wave(6, 0.08, t, rate), 0, 0);
        }
        case CameraMotionKind::Loop:
            return alongLoop(t);
    }
    return base;
}
}  // namespace smap::sim
