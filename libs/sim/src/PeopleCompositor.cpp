#include "smap/sim/PeopleCompositor.h"

#include <mrpt/core/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "smap/core/InputError.h"

namespace smap::sim
{
namespace
{
Eigen::Matrix3d rotation(const mrpt::poses::CPose3D& p)
{
    return p.getRotationMatrix().asEigen();
}
Eigen::Vector3d translation(const mrpt::poses::CPose3D& p)
{
    return {p.x(), p.y(), p.z()};
}
}  // namespace

CompositeScenario compositeScenarioFromString(const std::string& name)
{
    for (const auto s :
         {CompositeScenario::Random, CompositeScenario::Crossing, CompositeScenario::Crowd,
          CompositeScenario::Seated, CompositeScenario::StopAndStay})
        if (toString(s) == name)
            return s;
    throw core::InputError("unknown --scenario '" + name +
                           "' (random, crossing, crowd, seated, stop_and_stay)");
}

std::string toString(CompositeScenario s)
{
    switch (s)
    {
        case CompositeScenario::Random:
            return "random";
        case CompositeScenario::Crossing:
            return "crossing";
        case CompositeScenario::Crowd:
            return "crowd";
        case CompositeScenario::Seated:
            return "seated";
        case CompositeScenario::StopAndStay:
            return "stop_and_stay";
    }
    return "random";
}

void CompositeLayout::validate() const
{
    if (!(distanceScale > 0.0 && distanceScale <= 10.0))
        throw core::InputError(
            mrpt::format("compositing: distance scale %g must be in (0, 10]", distanceScale));
}

size_t defaultPeopleCount(CompositeScenario s)
{
    switch (s)
    {
        case CompositeScenario::Crowd:
            return 3;
        case CompositeScenario::StopAndStay:
            return 1;
        default:
            return 2;
    }
}

Eigen::Vector3d CompositedPerson::feetAt(double t) const
{
    if (sway)
        return start + halfRange * std::sin(2.0 * M_PI * (t + phase) / swayPeriod) * direction;
    if (dwell > 0.0)
    {
        // Walk -halfRange -> +halfRange, stand, walk back, stand.
        const double walk = 2.0 * halfRange / speed;
        const double tau = std::fmod(t + phase, 2.0 * (walk + dwell));
        double x = -halfRange;
        if (tau < walk)
            x = -halfRange + speed * tau;
        else if (tau < walk + dwell)
            x = halfRange;
        else if (tau < 2.0 * walk + dwell)
            x = halfRange - speed * (tau - walk - dwell);
        return start + x * direction;
    }
    // Back and forth (a triangle wave) along the direction, at constant speed.
    const double period = 4.0 * halfRange / speed;
    const double s = std::fmod(t + phase, period) / period;  // 0..1
    const double x =
        s < 0.5 ? -halfRange + 4.0 * halfRange * s : 3.0 * halfRange - 4.0 * halfRange * s;
    return start + x * direction;
}

namespace
{
using Probes = std::vector<PeopleCompositor::Probe>;

/// Prior for "up": image up (-y of the optical frame) averaged over the trajectory. It is biased
/// by the camera's mean pitch, so it only seeds the floor fit.
Eigen::Vector3d upPrior(const core::Trajectory& T_world_cam)
{
    Eigen::Vector3d prior = Eigen::Vector3d::Zero();
    for (const auto& p : T_world_cam)
        prior -= rotation(p.T_world_cam).col(1);
    return prior.normalized();
}

/// World points seen by the probes, every 6th pixel in u and v.
std::vector<Eigen::Vector3d> probeWorldPoints(const Probes& probes)
{
    constexpr int kStep = 6;
    std::vector<Eigen::Vector3d> points;
    for (const auto& pr : probes)
    {
        const Eigen::Matrix3d R = rotation(pr.T_world_cam);
        const Eigen::Vector3d c = translation(pr.T_world_cam);
        for (int v = 0; v < pr.frame.depth.rows; v += kStep)
        {
            for (int u = 0; u < pr.frame.depth.cols; u += kStep)
            {
                const float z = pr.frame.depth.at<float>(v, u);
                if (z > 0)
                    points.push_back(R * pr.frame.camera.unproject(u, v, z) + c);
            }
        }
    }
    return points;
}

struct FloorPlane
{
    Eigen::Vector3d up;
    double height = 0.0;  ///< along up
    size_t inliers = 0;
};

/// RANSAC plane among `points` (the lowest along the prior), within 35 degrees of horizontal.
FloorPlane fitFloorPlane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& prior,
                         uint32_t seed)
{
    constexpr int kIterations = 300;
    constexpr double kInlierDistance = 0.02;  // m
    const double minCos = std::cos(35.0 * M_PI / 180.0);
    std::mt19937 rngPlane(seed ^ 0x5eedu);
    std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
    FloorPlane best{prior, prior.dot(points[points.size() / 30]), 0};
    for (int it = 0; it < kIterations; it++)
    {
        const Eigen::Vector3d& a = points[pick(rngPlane)];
        const Eigen::Vector3d& b = points[pick(rngPlane)];
        const Eigen::Vector3d& c = points[pick(rngPlane)];
        Eigen::Vector3d n = (b - a).cross(c - a);
        if (n.norm() < 1e-9)
            continue;
        n.normalize();
        if (n.dot(prior) < 0)
            n = -n;
        if (n.dot(prior) < minCos)
            continue;
        const double d = n.dot(a);
        size_t inliers = 0;
        for (const auto& q : points)
            inliers += std::abs(n.dot(q) - d) < kInlierDistance ? 1 : 0;
        if (inliers > best.inliers)
            best = {n, d, inliers};
    }
    return best;
}

/// A table or a counter can out-vote the floor when the camera looks down at it. Floor and
/// table are parallel: along the plane's normal, the lowest 4 cm slab holding at least a
/// quarter of its support, more than 20 cm below it, is the floor. Returns the floor height.
double lowestParallelSlab(const std::vector<Eigen::Vector3d>& points, const FloorPlane& plane)
{
    constexpr double kSlab = 0.04, kBelow = 0.2;  // m
    std::vector<double> heights;
    heights.reserve(points.size());
    for (const auto& q : points)
        heights.push_back(plane.up.dot(q));
    std::sort(heights.begin(), heights.end());
    size_t end = 0;
    for (size_t i = 0; i < heights.size(); ++i)
    {
        end = std::max(end, i);
        while (end < heights.size() && heights[end] < heights[i] + kSlab)
            end++;
        const double centre = heights[(i + end) / 2];
        if (centre > plane.height - kBelow)
            break;
        if (4 * (end - i) >= plane.inliers)
            return centre;
    }
    return plane.height;
}

/// Whether world point X is inside a surface some probe sees, and whether some probe sees
/// through it (free space).
std::pair<bool, bool> insideOrSeenFree(const Eigen::Vector3d& X, const Probes& probes)
{
    bool seenFree = false, inside = false;
    for (const auto& pr : probes)
    {
        const Eigen::Vector3d Xc =
            rotation(pr.T_world_cam).transpose() * (X - translation(pr.T_world_cam));
        if (Xc.z() < 0.3)
            continue;
        const Eigen::Vector2d uv = pr.frame.camera.project(Xc);
        const long u = std::lround(uv.x()), v = std::lround(uv.y());
        if (u < 0 || v < 0 || u >= pr.frame.camera.width || v >= pr.frame.camera.height)
            continue;
        const float z = pr.frame.depth.at<float>(static_cast<int>(v), static_cast<int>(u));
        if (z <= 0)
            continue;
        if (std::abs(z - Xc.z()) < 0.2)
            inside = true;
        if (z > Xc.z() + 0.2)
            seenFree = true;
    }
    return {inside, seenFree};
}

/// Body samples (feet to head, left to right) of a walking line that are not known to be free
/// space: inside a surface some probe sees, or seen free by no probe (hidden behind walls or
/// furniture, or never in view).
FreeSpaceCheck collisions(const CompositedPerson& p, const Eigen::Vector3d& up,
                          const Probes& probes)
{
    FreeSpaceCheck c;
    for (double x = -p.halfRange; x <= p.halfRange + 1e-9; x += p.halfRange / 4)
    {
        // From 0.35 m up: rays through lower samples meet the floor just behind them.
        for (double h = 0.35; h < p.height; h += 0.2)
        {
            for (double a : {-0.2, 0.0, 0.2})
            {
                const Eigen::Vector3d X =
                    p.start + x * p.direction + h * up + a * up.cross(p.direction);
                const auto [inside, seenFree] = insideOrSeenFree(X, probes);
                c.samples++;
                c.inside += inside ? 1 : 0;
                c.unseen += (!inside && !seenFree) ? 1 : 0;
            }
        }
    }
    return c;
}

/// The random draws of a walking line, in the order the published composites drew them.
struct PlacementDraws
{
    std::mt19937 rng;
    std::uniform_real_distribution<double> dist{1.2, 3.5}, lateral{-1.0, 1.0}, speed{0.5, 1.3},
        height{1.6, 1.85}, phase{0.0, 5.0};
    std::uniform_real_distribution<double> heading{-1.0, 1.0}, range{0.5, 1.0};
    explicit PlacementDraws(uint32_t seed) : rng(seed) {}
};

/// Person i walks in front of probe i * probes / count, so that people are spread over the
/// sequence rather than all left behind at its start: of up to 200 random walking lines, the
/// first with all its body samples in known free space, else the one with the fewest outside.
/// What a scenario changes in a drawn walking line (Random: nothing, so that its composites stay
/// those published before scenarios existed).
void applyScenario(CompositeScenario scenario, double unit, CompositedPerson& p,
                   const Eigen::Vector3d& ground, const Eigen::Vector3d& forward,
                   const Eigen::Vector3d& side)
{
    // `unit` is a fresh draw in [0, 1): the scenario's own spread.
    switch (scenario)
    {
        case CompositeScenario::Random:
            return;
        case CompositeScenario::Crossing:
            p.start = ground + (1.5 + 1.5 * unit) * forward + (unit - 0.5) * side;
            p.direction = side * (p.instanceId % 2 == 0 ? -1.0 : 1.0);
            p.halfRange = 1.2 + 0.3 * unit;
            p.speed = 1.0 + 0.3 * unit;
            return;
        case CompositeScenario::Crowd:
            p.start = ground + (0.9 + 0.7 * unit) * forward + (1.2 * unit - 0.6) * side;
            p.halfRange = 0.8 + 0.4 * unit;
            p.speed = 1.3 + 0.5 * unit;
            return;
        case CompositeScenario::Seated:
            p.start = ground + (1.5 + 1.5 * unit) * forward + (2.0 * unit - 1.0) * side;
            p.sway = true;
            p.halfRange = 0.05 + 0.1 * unit;
            p.swayPeriod = 2.0 + unit;
            p.height = 1.25 + 0.1 * unit;
            return;
        case CompositeScenario::StopAndStay:
            p.start = ground + (1.5 + 1.0 * unit) * forward;
            p.direction = side;
            p.halfRange = 1.0 + 0.5 * unit;
            p.speed = 0.8 + 0.4 * unit;
            p.dwell = 5.0;
            p.phase = 0.0;
            return;
    }
}

std::pair<CompositedPerson, FreeSpaceCheck> placePerson(const std::vector<cv::Mat>& sprites,
                                                        const Probes& probes,
                                                        const Eigen::Vector3d& up,
                                                        double floorHeight, size_t i, size_t count,
                                                        uint32_t seed, PlacementDraws& draws,
                                                        const CompositeLayout& layout)
{
    constexpr int kAttempts = 200;
    // A crowd gathers in front of one frame, the middle one; the others spread over the frames.
    const CompositeScenario scenario = layout.scenario;
    const size_t anchorIndex =
        scenario == CompositeScenario::Crowd ? probes.size() / 2 : i * probes.size() / count;
    const auto& anchor = probes[anchorIndex].T_world_cam;
    Eigen::Vector3d forward = rotation(anchor).col(2);
    forward -= up * up.dot(forward);
    forward.normalize();
    const Eigen::Vector3d side = up.cross(forward).normalized();
    const Eigen::Vector3d c0 = translation(anchor);
    const Eigen::Vector3d ground = c0 - up * (up.dot(c0) - floorHeight);
    CompositedPerson best;
    FreeSpaceCheck bestCheck;
    size_t bestHits = std::numeric_limits<size_t>::max();
    for (int attempt = 0; attempt < kAttempts && bestHits > 0; attempt++)
    {
        CompositedPerson p;
        p.sprite = sprites[(seed + i) % sprites.size()];
        p.height = draws.height(draws.rng);
        p.start = ground + draws.dist(draws.rng) * forward + draws.lateral(draws.rng) * side;
        // Mostly across the anchor view, up to +-1 rad off it.
        const double ang = draws.heading(draws.rng);
        p.direction = (std::cos(ang) * side + std::sin(ang) * forward) * (i % 2 == 0 ? 1.0 : -1.0);
        p.halfRange = draws.range(draws.rng);
        p.speed = draws.speed(draws.rng);
        p.phase = draws.phase(draws.rng);
        p.instanceId = static_cast<uint16_t>(i + 1);
        if (scenario != CompositeScenario::Random)
            applyScenario(scenario, std::uniform_real_distribution<double>(0.0, 1.0)(draws.rng), p,
                          ground, forward, side);
        p.start += (layout.distanceScale - 1.0) * forward.dot(p.start - ground) * forward;
        const FreeSpaceCheck check = collisions(p, up, probes);
        if (check.inside + check.unseen < bestHits)
        {
            bestHits = check.inside + check.unseen;
            bestCheck = check;
            best = p;
        }
    }
    return {best, bestCheck};
}
}  // namespace

PeopleCompositor::PeopleCompositor(const std::vector<cv::Mat>& sprites,
                                   const core::Trajectory& T_world_cam,
                                   const std::vector<Probe>& probes, size_t count, uint32_t seed,
                                   const CompositeLayout& layout)
{
    if (sprites.empty() || T_world_cam.empty() || probes.empty())
        throw core::InputError("compositing needs cut-outs, a ground-truth trajectory and a frame");
    layout.validate();
    const Eigen::Vector3d prior = upPrior(T_world_cam);
    std::vector<Eigen::Vector3d> points = probeWorldPoints(probes);
    constexpr size_t kMinFloorPoints = 200;
    if (points.size() < kMinFloorPoints)
        throw core::InputError(
            "compositing: the frames have too little valid depth to find the floor");
    // Floor: among the lowest 30% of points (along the prior); its normal becomes "up" and its
    // offset the floor height.
    std::sort(points.begin(), points.end(),
              [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b)
              { return prior.dot(a) < prior.dot(b); });
    points.resize(points.size() * 3 / 10);
    const FloorPlane plane = fitFloorPlane(points, prior, seed);
    up_ = plane.up;
    floorHeight_ = lowestParallelSlab(points, plane);

    PlacementDraws draws(seed);
    for (size_t i = 0; i < count; i++)
    {
        const auto [person, check] =
            placePerson(sprites, probes, up_, floorHeight_, i, count, seed, draws, layout);
        freeSpace_.samples += check.samples;
        freeSpace_.inside += check.inside;
        freeSpace_.unseen += check.unseen;
        people_.push_back(person);
        // Flat, unfiltered: the compositing of the first published composites.
        billboards_.emplace_back(person.sprite, BillboardStyle{});
    }
}

CompositeFrame PeopleCompositor::composite(const core::RgbdFrame& frame,
                                           const mrpt::poses::CPose3D& T_world_cam, double t) const
{
    CompositeFrame out;
    out.colour = frame.colour.clone();
    out.depth = frame.depth.clone();
    out.labels = cv::Mat(frame.colour.size(), CV_8UC1, cv::Scalar(kUnknownLabel));
    out.instances = cv::Mat::zeros(frame.colour.size(), CV_16UC1);
    out.dynamic = cv::Mat::zeros(frame.colour.size(), CV_8UC1);
    BillboardLayers layers{out.colour, out.depth, out.labels, out.instances, out.dynamic};
    const Eigen::Vector3d c = translation(T_world_cam);

    // Nearest person first is not needed: the per-pixel depth test resolves their order.
    for (size_t i = 0; i < people_.size(); i++)
    {
        const CompositedPerson& p = people_[i];
        const Eigen::Vector3d feet = p.feetAt(t);
        Eigen::Vector3d n = c - feet;  // billboard faces the camera, stays vertical
        n -= up_ * up_.dot(n);
        if (n.norm() < 1e-6)
            continue;
        n.normalize();
        // World pose of the person's root: x forward (towards the camera), z up.
        Eigen::Matrix3d Rp;
        Rp.col(0) = n;
        Rp.col(1) = up_.cross(n);
        Rp.col(2) = up_;
        mrpt::math::CMatrixDouble33 Rm;
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                Rm(r, k) = Rp(r, k);
        mrpt::math::CVectorFixedDouble<3> tv;
        tv[0] = feet.x();
        tv[1] = feet.y();
        tv[2] = feet.z();
        out.objectPoses.emplace_back("person" + std::to_string(p.instanceId),
                                     mrpt::poses::CPose3D(Rm, tv));

        BillboardPose pose;
        pose.feet = feet;
        pose.normal = n;
        pose.up = up_;
        pose.height = p.height;
        // Composited people always move: every pixel of theirs is dynamic.
        billboards_[i].draw(pose, nullptr, frame.camera, T_world_cam, 15, p.instanceId, layers);
    }
    return out;
}
}  // namespace smap::sim
