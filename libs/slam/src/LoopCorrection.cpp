#include "smap/slam/LoopCorrection.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "smap/slam/Map.h"
#include "smap/slam/MapCorrection.h"
#include "smap/slam/ProjectionSearch.h"

namespace smap::slam
{
namespace
{
constexpr int kEssentialWeight = 100;  ///< covisibility that makes a pose-graph edge
constexpr double kMinChainWeight = 0.01;
constexpr int kLoopNeighbours = 10;
constexpr double kFuseRadius = 4.0;

using Poses = std::map<uint64_t, Eigen::Isometry3d>;

PoseGraphEdge edgeBetween(uint64_t i, uint64_t j, const Poses& T_cam_world, double weight = 1.0)
{
    return {i, j, T_cam_world.at(i) * T_cam_world.at(j).inverse(), weight};
}

/// How much a relative pose between two keyframes is worth: fully when they share
/// kEssentialWeight points, little when they share none (the step over a re-anchoring, where
/// the pose was extrapolated: the correction should go there).
double chainWeight(const KeyFrame& a, const KeyFrame& b)
{
    const double shared = a.weight(&b);
    return std::max(kMinChainWeight, std::sqrt(std::min(1.0, shared / kEssentialWeight)));
}

/// Consecutive keyframes, and strongly covisible ones, with their relative poses as they are.
std::vector<PoseGraphEdge> graphEdges(const Map& map, const Poses& old)
{
    std::vector<PoseGraphEdge> edges;
    uint64_t previous = old.begin()->first;
    for (const auto& [id, T] : old)
    {
        if (id != previous)
            edges.push_back(
                edgeBetween(previous, id, old,
                            chainWeight(*map.keyframes().at(previous), *map.keyframes().at(id))));
        previous = id;
        for (const KeyFrame* c : map.keyframes().at(id)->bestCovisibles())
            if (c->id() > id && old.count(c->id()) &&
                map.keyframes().at(id)->weight(c) >= kEssentialWeight)
                edges.push_back(edgeBetween(id, c->id(), old));
    }
    return edges;
}

std::vector<KeyFrame*> liveWindow(KeyFrame* centre, int n)
{
    std::vector<KeyFrame*> out = {centre};
    for (KeyFrame* c : centre->bestCovisibles(n))
        if (!c->isBad())
            out.push_back(c);
    return out;
}

struct GraphCopy
{
    Poses old, initial;
    std::vector<PoseGraphEdge> edges;
    std::set<uint64_t> fixed;
};

GraphCopy copyGraph(Map& map, KeyFrame& kf, const LoopMatch& match,
                    std::vector<PoseGraphEdge>& loopEdges)
{
    GraphCopy g;
    // The loop's part of the map alone: another part shares nothing with it (the rest of the
    // map follows the newest keyframe rigidly, MapCorrection.h).
    for (const auto& [id, k] : map.keyframes())
        if (k->part() == kf.part())
            g.old[id] = k->T_cam_world();
    g.initial = g.old;
    // The new keyframe's neighbourhood moves rigidly with it to where the loop puts it.
    const Eigen::Isometry3d T_kf_old = kf.T_cam_world();
    for (KeyFrame* w : liveWindow(&kf, -1))
        g.initial[w->id()] = w->T_cam_world() * T_kf_old.inverse() * match.T_cam_world;
    loopEdges.push_back(
        {match.loop->id(), kf.id(), match.loop->T_cam_world() * match.T_cam_world.inverse(), 1.0});
    g.edges = graphEdges(map, g.old);
    g.edges.insert(g.edges.end(), loopEdges.begin(), loopEdges.end());
    g.fixed = {g.old.begin()->first, match.loop->id()};
    return g;
}

/// Runs one step of a fusion under the map mutex when given the map (a consistent revisit:
/// tracking then waits for one keyframe's share at most, not for the whole fusion; a waiting
/// tracker goes first), else as it is (the caller holds the map mutex: a correction, which the
/// tracker must see whole).
template <class Step>
auto stepLocked(Map* map, Step&& step)
{
    if (!map)
        return step();
    constexpr auto kPause = std::chrono::microseconds(100);
    while (map->trackingWaits())
        std::this_thread::sleep_for(kPause);
    std::lock_guard<std::mutex> lock(map->mutex());
    return step();
}

/// The new keyframe's side and the loop's side, and the loop side's points, read in one step.
struct LoopSides
{
    std::vector<KeyFrame*> kfSide, loopSide;
    std::vector<std::shared_ptr<MapPoint>> loopPoints;
};

LoopSides readLoopSides(KeyFrame& kf, KeyFrame& loop)
{
    LoopSides sides;
    if (kf.isBad() || loop.isBad())
        return sides;
    std::set<uint64_t> ids;
    sides.loopSide = liveWindow(&loop, kLoopNeighbours);
    for (KeyFrame* k : sides.loopSide)
        for (const auto& mp : k->points)
            if (mp && !mp->isBad() && ids.insert(mp->id()).second)
                sides.loopPoints.push_back(mp);
    sides.kfSide = liveWindow(&kf, -1);
    return sides;
}

/// The points of `w` not refreshed yet in this fusion (`done`), refreshed: each point once,
/// though it is seen by many of the keyframes (the same result as refreshing it for each).
void refreshPointsOnce(const KeyFrame& w, std::set<uint64_t>& done)
{
    for (const auto& mp : w.points)
    {
        if (mp && !mp->isBad() && done.insert(mp->id()).second)
        {
            mp->computeDistinctiveDescriptor();
            mp->updateNormalAndDepth();
        }
    }
}

/// The loop side's points fused into every keyframe of the new keyframe's side, that side's
/// points refreshed and both sides' covisibility updated, each keyframe's share a step of its
/// own. Keyframes are never freed (Map::allKeyFrames), so the pointers stay valid between
/// steps; one culled meanwhile is skipped.
int fuseAcrossLoop(KeyFrame& kf, KeyFrame& loop, int covisibility_min_weight, Map* stepMap)
{
    const auto locked = [stepMap](auto&& step) { return stepLocked(stepMap, step); };
    const LoopSides sides = locked([&] { return readLoopSides(kf, loop); });
    int fused = 0;
    for (KeyFrame* w : sides.kfSide)
        fused += locked([&] { return w->isBad() ? 0 : fuse(*w, sides.loopPoints, kFuseRadius); });
    std::set<uint64_t> refreshed;
    for (KeyFrame* w : sides.kfSide)
    {
        locked(
            [&]
            {
                if (!w->isBad())
                    refreshPointsOnce(*w, refreshed);
            });
    }
    for (const auto* side : {&sides.kfSide, &sides.loopSide})
    {
        for (KeyFrame* w : *side)
        {
            locked(
                [&]
                {
                    if (!w->isBad())
                        w->updateConnections(covisibility_min_weight);
                });
        }
    }
    return fused;
}
}  // namespace

int joinConsistentRevisit(Map& map, const std::shared_ptr<KeyFrame>& kf, const LoopMatch& match,
                          std::vector<PoseGraphEdge>& loopEdges, int covisibility_min_weight)
{
    {
        std::lock_guard<std::mutex> lock(map.mutex());
        if (kf->isBad() || match.loop->isBad())
            return 0;
        loopEdges.push_back({match.loop->id(), kf->id(),
                             match.loop->T_cam_world() * match.T_cam_world.inverse(), 1.0});
    }
    return fuseAcrossLoop(*kf, *match.loop, covisibility_min_weight, &map);
}

LoopCorrectionOutcome correctLoop(Map& map, const std::shared_ptr<KeyFrame>& kf,
                                  const LoopMatch& match, std::vector<PoseGraphEdge>& loopEdges,
                                  int iterations, int covisibility_min_weight)
{
    GraphCopy g;
    {
        std::lock_guard<std::mutex> lock(map.mutex());
        if (kf->isBad() || match.loop->isBad())
            return {};
        g = copyGraph(map, *kf, match, loopEdges);
    }
    Poses corrected = g.initial;
    optimisePoseGraph(corrected, g.edges, g.fixed, iterations);
    LoopCorrectionOutcome out;
    out.T_loop_keyframe = loopEdges.back().T_i_j;
    out.keyframes = static_cast<int>(corrected.size());
    std::lock_guard<std::mutex> lock(map.mutex());
    const Eigen::Isometry3d before = kf->T_cam_world();
    applyCorrections(map, correctionsBetween(g.old, corrected));
    const Eigen::Isometry3d moved = before.inverse() * kf->T_cam_world();
    out.moved_m = (kf->centre_world() - before.inverse().translation()).norm();
    out.turned_deg = Eigen::AngleAxisd(moved.rotation()).angle() * 180.0 / M_PI;
    out.pointsFused = fuseAcrossLoop(*kf, *match.loop, covisibility_min_weight, nullptr);
    map.noteCorrection();
    return out;
}
}  // namespace smap::slam
