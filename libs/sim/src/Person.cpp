#include "smap/sim/Person.h"

#include <cmath>
#include <stdexcept>

namespace smap::sim
{
namespace
{
/// Sitting: the feet (the sprite's bottom) rest this far in front of the seat's centre.
constexpr double kFeetAheadOfSeat = 0.22;

/// Unit horizontal vector from `from` towards `to`; +x when they coincide.
Eigen::Vector3d towards(const Eigen::Vector2d& from, const Eigen::Vector2d& to)
{
    const Eigen::Vector2d d = to - from;
    return d.norm() < 1e-9 ? Eigen::Vector3d::UnitX()
                           : Eigen::Vector3d(d.x(), d.y(), 0.0).normalized();
}
}  // namespace

Person::Person(const PersonSpec& spec, uint16_t instanceId) : spec_(spec), instanceId_(instanceId)
{
    if (spec.kind == PersonSpec::Kind::Walking)
    {
        if (spec.path.size() < 2)
            throw std::invalid_argument("a walking person needs a path of at least 2 points");
        for (size_t i = 0; i < spec.path.size(); i++)
            pathLength_ += (spec.path[(i + 1) % spec.path.size()] - spec.path[i]).norm();
    }
}

Eigen::Vector2d Person::pointOnPath(double s) const
{
    s = std::fmod(s, pathLength_);
    if (s < 0)
        s += pathLength_;
    for (size_t i = 0; i < spec_.path.size(); i++)
    {
        const Eigen::Vector2f a = spec_.path[i], b = spec_.path[(i + 1) % spec_.path.size()];
        const double len = (b - a).norm();
        if (s <= len)
            return (a + (b - a) * static_cast<float>(s / len)).cast<double>();
        s -= len;
    }
    return spec_.path.front().cast<double>();
}

mrpt::poses::CPose3D Person::rootPose(double t) const
{
    if (spec_.kind == PersonSpec::Kind::Sitting)
    {
        const Eigen::Vector3d f = towards(spec_.seat.cast<double>(), spec_.viewer.cast<double>());
        return {spec_.seat.x(), spec_.seat.y(), 0.0, std::atan2(f.y(), f.x()), 0, 0};
    }
    const double s = (t + spec_.phase) * spec_.speed;
    const Eigen::Vector2d p = pointOnPath(s);
    // Heading towards a point ahead on the path, and from one behind: turns are smooth.
    const Eigen::Vector2d dir = pointOnPath(s + 0.5) - pointOnPath(s - 0.5);
    return {p.x(), p.y(), 0.0, std::atan2(dir.y(), dir.x()), 0, 0};
}

BillboardPose Person::billboard(double t) const
{
    BillboardPose b;
    b.height = spec_.height;
    const double tt = t + spec_.phase;
    const mrpt::poses::CPose3D root = rootPose(t);
    const Eigen::Vector2d ground(root.x(), root.y());
    b.normal = towards(ground, spec_.viewer.cast<double>());
    if (spec_.kind == PersonSpec::Kind::Walking)
    {
        // One gait cycle (two steps) per ~1.4 m travelled: a bob on each step, a sideways
        // rock of the whole body once per cycle.
        const double w = 2.0 * M_PI * spec_.speed / 1.4;
        b.feet = Eigen::Vector3d(ground.x(), ground.y(), 0.02 * std::abs(std::cos(w * tt)));
        b.leanAcross = 0.03 * std::sin(w * tt);
        return b;
    }
    b.feet = Eigen::Vector3d(ground.x(), ground.y(), 0.0) + kFeetAheadOfSeat * b.normal;
    b.pivotHeight = spec_.seatHeight;
    b.leanTowards = 0.08 * std::sin(2.0 * M_PI * 0.3 * tt);
    b.leanAcross = 0.05 * std::sin(2.0 * M_PI * 0.45 * tt + 1.0);
    return b;
}
}  // namespace smap::sim
