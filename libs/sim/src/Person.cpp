#include "smap/sim/Person.h"

#include <cmath>
#include <stdexcept>

namespace smap::sim
{
namespace
{
enum Part
{
    kTorso,
    kHead,
    kLeftArm,
    kRightArm,
    kLeftThigh,
    kRightThigh,
    kLeftShin,
    kRightShin,
    kPartCount
};

struct Dimensions
{
    float legLength, thighLength, shinLength, hipHeight, torsoHeight, torsoWidth, torsoDepth;
    float headSize, armLength, armThickness, legThickness, hipSeparation;
};

Dimensions dimensionsFor(float h)
{
    Dimensions d{};
    d.legLength = 0.48f * h;
    d.thighLength = 0.5f * d.legLength;
    d.shinLength = 0.5f * d.legLength;
    d.hipHeight = d.legLength;
    d.torsoHeight = 0.30f * h;
    d.torsoWidth = 0.22f * h;
    d.torsoDepth = 0.12f * h;
    d.headSize = 0.13f * h;
    d.armLength = 0.36f * h;
    d.armThickness = 0.05f * h;
    d.legThickness = 0.075f * h;
    d.hipSeparation = 0.055f * h;
    return d;
}

mrpt::poses::CPose3D pitch(double a)
{
    return {0, 0, 0, 0, a, 0};
}
mrpt::poses::CPose3D offset(double x, double y, double z)
{
    return {x, y, z, 0, 0, 0};
}
}  // namespace

Person::Person(const PersonSpec& spec, uint16_t instanceId, int shirtTexture, int trousersTexture,
               int skinTexture, uint32_t seed)
    : spec_(spec), instanceId_(instanceId)
{
    if (spec.kind == PersonSpec::Kind::Walking)
    {
        if (spec.path.size() < 2)
            throw std::invalid_argument("a walking person needs a path of at least 2 points");
        for (size_t i = 0; i < spec.path.size(); i++)
            pathLength_ += (spec.path[(i + 1) % spec.path.size()] - spec.path[i]).norm();
    }
    const Dimensions d = dimensionsFor(spec.height);
    const char* names[kPartCount] = {"torso",      "head",        "left_arm",  "right_arm",
                                     "left_thigh", "right_thigh", "left_shin", "right_shin"};
    parts_.resize(kPartCount);
    for (int p = 0; p < kPartCount; p++)
    {
        auto& o = parts_[static_cast<size_t>(p)];
        o.name = std::string("person") + std::to_string(instanceId) + "_" + names[p];
        o.classId = voc::kPerson;
        o.instanceId = instanceId;
        o.textureIndex =
            p == kHead ? skinTexture : (p <= kRightArm ? shirtTexture : trousersTexture);
    }
    const float cell = 0.5f;
    addBox(parts_[kTorso], {0, 0, d.torsoHeight / 2}, {d.torsoDepth, d.torsoWidth, d.torsoHeight},
           cell, seed + 10);
    addBox(parts_[kHead], {0.01f, 0, d.headSize / 2},
           {d.headSize * 0.85f, d.headSize * 0.75f, d.headSize}, cell, seed + 20);
    for (int p : {kLeftArm, kRightArm})
        addBox(parts_[static_cast<size_t>(p)], {0, 0, -d.armLength / 2},
               {d.armThickness, d.armThickness, d.armLength}, cell, seed + 30 + p);
    for (int p : {kLeftThigh, kRightThigh})
        addBox(parts_[static_cast<size_t>(p)], {0, 0, -d.thighLength / 2},
               {d.legThickness, d.legThickness, d.thighLength}, cell, seed + 40 + p);
    for (int p : {kLeftShin, kRightShin})
        addBox(parts_[static_cast<size_t>(p)], {0, 0, -d.shinLength / 2},
               {d.legThickness * 0.85f, d.legThickness * 0.85f, d.shinLength}, cell, seed + 50 + p);
}

mrpt::poses::CPose3D Person::rootPose(double t) const
{
    if (spec_.kind == PersonSpec::Kind::Sitting)
        return {spec_.seat.x(), spec_.seat.y(), 0.0, spec_.facing, 0, 0};
    auto pointAt = [&](double s)
    {
        s = std::fmod(s, pathLength_);
        if (s < 0)
            s += pathLength_;
        for (size_t i = 0; i < spec_.path.size(); i++)
        {
            const Eigen::Vector2f a = spec_.path[i], b = spec_.path[(i + 1) % spec_.path.size()];
            const double len = (b - a).norm();
            if (s <= len)
                return Eigen::Vector2d((a + (b - a) * static_cast<float>(s / len)).cast<double>());
            s -= len;
        }
        return spec_.path.front().cast<double>().eval();
    };
    const double s = (t + spec_.phase) * spec_.speed;
    const Eigen::Vector2d p = pointAt(s);
    // Heading towards a point ahead on the path, and from one behind: turns are smooth.
    const Eigen::Vector2d dir = pointAt(s + 0.5) - pointAt(s - 0.5);
    return {p.x(), p.y(), 0.0, std::atan2(dir.y(), dir.x()), 0, 0};
}

std::vector<mrpt::poses::CPose3D> Person::partPoses(double t) const
{
    const Dimensions d = dimensionsFor(spec_.height);
    std::vector<mrpt::poses::CPose3D> poses(kPartCount);
    const mrpt::poses::CPose3D root = rootPose(t);
    const double tt = t + spec_.phase;
    if (spec_.kind == PersonSpec::Kind::Walking)
    {
        // One gait cycle (two steps) per ~1.4 m travelled.
        const double w = 2.0 * M_PI * spec_.speed / 1.4;
        const double c = std::sin(w * tt);
        const double bob = 0.02 * std::abs(std::cos(w * tt));
        const auto hips = root + offset(0, 0, d.hipHeight + bob);
        poses[kTorso] = hips + pitch(0.05);  // slight forward lean
        poses[kHead] = poses[kTorso] + offset(0, 0, d.torsoHeight + 0.02);
        const double legSwing = 0.45, armSwing = 0.35;
        poses[kLeftThigh] = hips + offset(0, d.hipSeparation, 0) + pitch(-legSwing * c);
        poses[kRightThigh] = hips + offset(0, -d.hipSeparation, 0) + pitch(legSwing * c);
        // Knees bend while the leg swings forward.
        const double kneeL = 0.6 * std::max(0.0, std::sin(w * tt - 0.8));
        const double kneeR = 0.6 * std::max(0.0, -std::sin(w * tt - 0.8));
        poses[kLeftShin] = poses[kLeftThigh] + offset(0, 0, -d.thighLength) + pitch(kneeL);
        poses[kRightShin] = poses[kRightThigh] + offset(0, 0, -d.thighLength) + pitch(kneeR);
        const double shoulder = d.torsoHeight - 0.04;
        const double arm = d.torsoWidth / 2 + d.armThickness / 2 + 0.005;
        poses[kLeftArm] = poses[kTorso] + offset(0, arm, shoulder) + pitch(armSwing * c);
        poses[kRightArm] = poses[kTorso] + offset(0, -arm, shoulder) + pitch(-armSwing * c);
    }
    else
    {
        const double sway = 0.05 * std::sin(2.0 * M_PI * 0.3 * tt);
        const auto hips = root + offset(0, 0, spec_.seatHeight);
        poses[kTorso] = hips + mrpt::poses::CPose3D(0, 0, 0, 0, sway, 0.5 * sway);
        poses[kHead] = poses[kTorso] + offset(0, 0, d.torsoHeight + 0.02) +
                       pitch(0.1 * std::sin(2.0 * M_PI * 0.4 * tt));
        for (int side : {0, 1})
        {
            const double y = side == 0 ? d.hipSeparation : -d.hipSeparation;
            const int thigh = side == 0 ? kLeftThigh : kRightThigh;
            const int shin = side == 0 ? kLeftShin : kRightShin;
            poses[static_cast<size_t>(thigh)] = hips + offset(0, y, 0) + pitch(-M_PI / 2);
            poses[static_cast<size_t>(shin)] =
                poses[static_cast<size_t>(thigh)] + offset(0, 0, -d.thighLength) + pitch(M_PI / 2);
        }
        const double shoulder = d.torsoHeight - 0.04;
        const double arm = d.torsoWidth / 2 + d.armThickness / 2 + 0.005;
        // The right arm gestures (raised forward and back), the left rests.
        const double gesture = 0.6 + 0.5 * std::sin(2.0 * M_PI * 0.5 * tt);
        poses[kLeftArm] = poses[kTorso] + offset(0, arm, shoulder) + pitch(-0.3);
        poses[kRightArm] = poses[kTorso] + offset(0, -arm, shoulder) + pitch(-gesture);
    }
    return poses;
}
}  // namespace smap::sim
