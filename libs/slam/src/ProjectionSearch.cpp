#include "smap/slam/ProjectionSearch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_set>

#include "Chi2.h"
#include "smap/features/DescriptorMatcher.h"
#include "smap/features/RotationConsistency.h"
#include "smap/slam/Frame.h"
#include "smap/slam/KeyFrame.h"
#include "smap/slam/MapPoint.h"

namespace smap::slam
{
namespace
{
/// Keypoints within this many pixels of a projected map point say whether a mover hides it.
constexpr float kOccluderRadius = 12.0F;

bool alreadyMatched(const std::shared_ptr<MapPoint>& p)
{
    return p && !p->isBad() && p->numObservations() > 0;
}

void rejectInconsistentRotations(Frame& frame, const features::RotationConsistency& rot, int& n)
{
    for (size_t i : rot.inconsistent())
    {
        if (frame.points[i])
        {
            frame.points[i].reset();
            n--;
        }
    }
}
}  // namespace

bool projectIntoImage(const Eigen::Isometry3d& T_cam_world, const core::PinholeCamera& camera,
                      const Eigen::Vector3d& p_world, Eigen::Vector3d& p_cam, Eigen::Vector2d& uv)
{
    p_cam = T_cam_world * p_world;
    if (p_cam.z() <= 1e-6)
        return false;
    uv = camera.project(p_cam);
    return uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() < camera.width && uv.y() < camera.height;
}

int searchFromLastFrame(Frame& current, const Frame& last, double radius)
{
    int n = 0;
    features::RotationConsistency rot;
    const auto& pyr = current.features.pyramid;
    for (size_t i = 0; i < last.size(); ++i)
    {
        const auto& mp = last.points[i];
        if (!mp || last.outlier[i] || mp->isBad())
            continue;
        Eigen::Vector3d pc;
        Eigen::Vector2d uv;
        if (!projectIntoImage(current.T_cam_world, current.camera, mp->position_world, pc, uv))
            continue;
        const int level = last.features.keypoints[i].octave;
        const double r = radius * pyr.scale[static_cast<size_t>(level)];
        const double uR = uv.x() - current.bf / pc.z();
        int best = std::numeric_limits<int>::max();
        size_t bestIdx = 0;
        for (size_t j : current.grid.query(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                           static_cast<float>(r), level - 1, level + 1))
        {
            if (!current.usable(j) || alreadyMatched(current.points[j]))
                continue;
            if (current.features.hasDepth(j) && std::abs(uR - current.features.rightU[j]) > r)
                continue;
            const int d =
                features::descriptorDistance(mp->descriptor.data(), current.features.descriptor(j));
            if (d < best)
            {
                best = d;
                bestIdx = j;
            }
        }
        if (best <= kDescriptorHigh)
        {
            if (!current.points[bestIdx])
                n++;
            current.points[bestIdx] = mp;
            current.outlier[bestIdx] = false;
            rot.add(bestIdx, last.features.keypoints[i].angle,
                    current.features.keypoints[bestIdx].angle);
        }
    }
    rejectInconsistentRotations(current, rot, n);
    return n;
}

namespace
{
/// Behind a mover: most keypoints around the projection are excluded (weight 0). Such a point
/// cannot be seen now, and must not count as "visible but not found", or people walking in
/// front of the background would get its map points culled.
bool hiddenByMover(const Frame& frame, const Eigen::Vector2d& uv)
{
    int excluded = 0, all = 0;
    for (size_t j :
         frame.grid.query(static_cast<float>(uv.x()), static_cast<float>(uv.y()), kOccluderRadius))
    {
        all++;
        excluded += frame.usable(j) ? 0 : 1;
    }
    return 2 * excluded > all;
}

/// The best unmatched keypoint for a map point within radius r of its projection (levels
/// level-1 .. level), when it passes the distance and ratio tests.
std::optional<size_t> bestLocalMatch(const Frame& frame, const MapPoint& mp,
                                     const Eigen::Vector2d& uv, double uR, double r, int level)
{
    int best = std::numeric_limits<int>::max(), second = best;
    int bestLevel = -1, secondLevel = -1;
    size_t bestIdx = 0;
    for (size_t j : frame.grid.query(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                     static_cast<float>(r), level - 1, level))
    {
        if (!frame.usable(j) || alreadyMatched(frame.points[j]))
            continue;
        if (frame.features.hasDepth(j) && std::abs(uR - frame.features.rightU[j]) > r)
            continue;
        const int d =
            features::descriptorDistance(mp.descriptor.data(), frame.features.descriptor(j));
        if (d < best)
        {
            second = best;
            secondLevel = bestLevel;
            best = d;
            bestLevel = frame.features.keypoints[j].octave;
            bestIdx = j;
        }
        else if (d < second)
        {
            second = d;
            secondLevel = frame.features.keypoints[j].octave;
        }
    }
    if (best > kDescriptorHigh || (bestLevel == secondLevel && best > 0.8 * second))
        return std::nullopt;
    return bestIdx;
}
}  // namespace

int searchLocalPoints(Frame& frame, const std::vector<std::shared_ptr<MapPoint>>& points,
                      double radius)
{
    const Eigen::Vector3d centre = frame.T_cam_world.inverse().translation();
    const auto& pyr = frame.features.pyramid;
    const bool anyExcluded =
        std::any_of(frame.weights.begin(), frame.weights.end(), [](float w) { return w <= 0.0F; });
    int n = 0;
    for (const auto& mp : points)
    {
        if (mp->isBad())
            continue;
        Eigen::Vector3d pc;
        Eigen::Vector2d uv;
        if (!projectIntoImage(frame.T_cam_world, frame.camera, mp->position_world, pc, uv))
            continue;
        const Eigen::Vector3d ray = mp->position_world - centre;
        const double dist = ray.norm();
        if (dist < mp->minDistance() || dist > mp->maxDistance())
            continue;
        const double viewCos = ray.dot(mp->normal()) / dist;
        if (viewCos < 0.5 || (anyExcluded && hiddenByMover(frame, uv)))
            continue;
        mp->increaseVisible();
        const int level = mp->predictLevel(dist, pyr);
        const double r =
            radius * (viewCos > 0.998 ? 2.5 : 4.0) * pyr.scale[static_cast<size_t>(level)];
        const auto match = bestLocalMatch(frame, *mp, uv, uv.x() - frame.bf / pc.z(), r, level);
        if (!match)
            continue;
        if (!frame.points[*match])
            n++;
        frame.points[*match] = mp;
        frame.outlier[*match] = false;
    }
    return n;
}

int searchKeyFramePoints(Frame& frame, const KeyFrame& kf, double radius, int max_distance)
{
    const Eigen::Vector3d centre = frame.T_cam_world.inverse().translation();
    const auto& pyr = frame.features.pyramid;
    features::RotationConsistency rot;
    std::unordered_set<const MapPoint*> matched;
    for (const auto& fp : frame.points)
        if (fp)
            matched.insert(fp.get());
    int n = 0;
    for (size_t i = 0; i < kf.points.size(); ++i)
    {
        const auto& mp = kf.points[i];
        if (!mp || mp->isBad())
            continue;
        if (matched.count(mp.get()))
            continue;
        Eigen::Vector3d pc;
        Eigen::Vector2d uv;
        if (!projectIntoImage(frame.T_cam_world, frame.camera, mp->position_world, pc, uv))
            continue;
        const double dist = (mp->position_world - centre).norm();
        if (dist < mp->minDistance() || dist > mp->maxDistance())
            continue;
        const int level = mp->predictLevel(dist, pyr);
        const double r = radius * pyr.scale[static_cast<size_t>(level)];
        int best = std::numeric_limits<int>::max();
        size_t bestIdx = 0;
        for (size_t j : frame.grid.query(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                         static_cast<float>(r), level - 1, level + 1))
        {
            if (!frame.usable(j) || frame.points[j])
                continue;
            const int d =
                features::descriptorDistance(mp->descriptor.data(), frame.features.descriptor(j));
            if (d < best)
            {
                best = d;
                bestIdx = j;
            }
        }
        if (best <= max_distance)
        {
            frame.points[bestIdx] = mp;
            frame.outlier[bestIdx] = false;
            n++;
            rot.add(bestIdx, kf.features.keypoints[i].angle,
                    frame.features.keypoints[bestIdx].angle);
        }
    }
    rejectInconsistentRotations(frame, rot, n);
    return n;
}

int matchProjectedPoint(const KeyFrame& kf, const Eigen::Isometry3d& T_cam_world,
                        const MapPoint& mp, double radius)
{
    Eigen::Vector3d pc;
    Eigen::Vector2d uv;
    if (!projectIntoImage(T_cam_world, kf.camera, mp.position_world, pc, uv))
        return -1;
    const Eigen::Vector3d ray = mp.position_world - T_cam_world.inverse().translation();
    const double dist = ray.norm();
    if (dist < mp.minDistance() || dist > mp.maxDistance() || ray.dot(mp.normal()) < 0.5 * dist)
        return -1;
    const auto& pyr = kf.features.pyramid;
    const int level = mp.predictLevel(dist, pyr);
    const double r = radius * pyr.scale[static_cast<size_t>(level)];
    const double uR = uv.x() - kf.bf / pc.z();
    int best = std::numeric_limits<int>::max();
    int bestIdx = -1;
    for (size_t j : kf.grid.query(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                  static_cast<float>(r), level - 1, level))
    {
        if (kf.weights[j] <= 0.0F)
            continue;
        const double ex = uv.x() - kf.features.undistorted[j].x;
        const double ey = uv.y() - kf.features.undistorted[j].y;
        const double info = pyr.invSigma2[static_cast<size_t>(kf.features.keypoints[j].octave)];
        double e2 = ex * ex + ey * ey;
        double chi2 = kChi2Mono;
        if (kf.features.hasDepth(j))
        {
            const double er = uR - kf.features.rightU[j];
            e2 += er * er;
            chi2 = kChi2Stereo;
        }
        if (e2 * info > chi2)
            continue;
        const int d = features::descriptorDistance(mp.descriptor.data(), kf.features.descriptor(j));
        if (d < best)
        {
            best = d;
            bestIdx = static_cast<int>(j);
        }
    }
    return best <= kDescriptorLow ? bestIdx : -1;
}

bool agreesWithKeypoint(const KeyFrame& kf, size_t j, const Eigen::Vector3d& p_world)
{
    const Eigen::Vector3d pc = kf.T_cam_world() * p_world;
    if (pc.z() <= 0.0)
        return false;
    const double u = kf.camera.fx * pc.x() / pc.z() + kf.camera.cx;
    const double v = kf.camera.fy * pc.y() / pc.z() + kf.camera.cy;
    const double ex = u - kf.features.undistorted[j].x;
    const double ey = v - kf.features.undistorted[j].y;
    double e2 = ex * ex + ey * ey;
    double chi2 = kChi2Mono;
    if (kf.features.hasDepth(j))
    {
        const double er = (u - kf.bf / pc.z()) - kf.features.rightU[j];
        e2 += er * er;
        chi2 = kChi2Stereo;
    }
    const auto level = static_cast<size_t>(kf.features.keypoints[j].octave);
    return e2 * kf.features.pyramid.invSigma2[level] <= chi2;
}

int matchFreeKeypoint(const KeyFrame& kf, const Eigen::Vector3d& p_world, int level,
                      const uint8_t* descriptor, double radius, double ratio)
{
    Eigen::Vector3d pc;
    Eigen::Vector2d uv;
    if (!projectIntoImage(kf.T_cam_world(), kf.camera, p_world, pc, uv))
        return -1;
    const double r = radius * kf.features.pyramid.scale[static_cast<size_t>(level)];
    int best = std::numeric_limits<int>::max();
    int second = std::numeric_limits<int>::max();
    int bestIdx = -1;
    for (size_t j : kf.grid.query(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                                  static_cast<float>(r), level - 1, level + 1))
    {
        const bool taken = kf.points[j] && !kf.points[j]->isBad();
        if (taken || !kf.canMap(j) || !kf.features.hasDepth(j) ||
            !agreesWithKeypoint(kf, j, p_world))
            continue;
        const int d = features::descriptorDistance(descriptor, kf.features.descriptor(j));
        if (d < best)
        {
            second = best;
            best = d;
            bestIdx = static_cast<int>(j);
        }
        else if (d < second)
        {
            second = d;
        }
    }
    if (best > kDescriptorLow || static_cast<double>(best) >= ratio * second)
        return -1;
    return bestIdx;
}

int fuse(KeyFrame& kf, const std::vector<std::shared_ptr<MapPoint>>& points, double radius)
{
    const Eigen::Isometry3d T = kf.T_cam_world();
    int n = 0;
    for (const auto& mp : points)
    {
        if (!mp || mp->isBad() || mp->isObservedBy(&kf))
            continue;
        const int found = matchProjectedPoint(kf, T, *mp, radius);
        if (found < 0)
            continue;
        const auto bestIdx = static_cast<size_t>(found);
        const std::shared_ptr<MapPoint> existing = kf.points[bestIdx];
        if (existing && !existing->isBad())
        {
            if (existing->numObservations() >= mp->numObservations())
                mp->replaceWith(existing);
            else
                existing->replaceWith(mp);
        }
        else
        {
            mp->addObservation(&kf, bestIdx);
            kf.points[bestIdx] = mp;
        }
        n++;
    }
    return n;
}
}  // namespace smap::slam
