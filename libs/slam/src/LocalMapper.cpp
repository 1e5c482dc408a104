#include "smap/slam/LocalMapper.h"

#include <chrono>
#include <set>

#include "KeyFrameQueue.h"
#include "TwoViewPoint.h"
#include "smap/core/Elapsed.h"
#include "smap/slam/Map.h"
#include "smap/slam/ProjectionSearch.h"

namespace smap::slam
{
using core::secondsSince;

LocalMapper::LocalMapper(Map& map, const LocalMappingParameters& params)
    : COutputLogger("local-mapping"),
      map_(map),
      params_(params),
      queue_(std::make_unique<KeyFrameQueue>(params_.threaded,
                                             [this](const std::shared_ptr<KeyFrame>& kf)
                                             {
                                                 abortBa_ = false;
                                                 process(kf);
                                             }))
{
}

LocalMapper::~LocalMapper()
{
    abortBa_ = true;
    queue_->stop();
}

void LocalMapper::insertKeyFrame(const std::shared_ptr<KeyFrame>& kf)
{
    queue_->push(kf);
}

bool LocalMapper::idle() const
{
    return queue_->idle();
}

size_t LocalMapper::queued() const
{
    return queue_->waiting();
}

void LocalMapper::waitUntilIdle()
{
    queue_->waitUntilIdle();
}

LocalMapper::Stats LocalMapper::stats() const
{
    std::lock_guard<std::mutex> lock(statsMutex_);
    return stats_;
}

void LocalMapper::process(const std::shared_ptr<KeyFrame>& kf)
{
    {
        waiting_ = true;
        std::lock_guard<std::mutex> still(processing_);
        waiting_ = false;
        processHeld(kf);
    }
    if (sink_)
        sink_(kf);
}

void LocalMapper::processHeld(const std::shared_ptr<KeyFrame>& kf)
{
    const auto t0 = std::chrono::steady_clock::now();
    {
        std::lock_guard<std::mutex> lock(map_.mutex());
        linkNewKeyFrame(kf);
        cullRecentPoints(*kf);
        createPointsWithNeighbours(kf);
        fuseWithNeighbours(kf);
    }
    // Bundle adjustment is skipped while more keyframes wait: they will run it.
    const bool moreWaiting = queue_->waiting() > 0;
    BundleAdjustmentStats ba;
    double baSeconds = 0.0;
    if (!moreWaiting && !abortBa_)
    {
        const auto tBa = std::chrono::steady_clock::now();
        ba = localBundleAdjustment(kf, map_, params_, abortBa_);
        baSeconds = secondsSince(tBa);
    }
    {
        std::lock_guard<std::mutex> lock(map_.mutex());
        cullKeyFrames(*kf);
        map_.removeBad();
    }
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_.pointsCulled += pending_.pointsCulled;
    stats_.pointsFused += pending_.pointsFused;
    stats_.pointsFromNeighbours += pending_.pointsFromNeighbours;
    stats_.keyframesCulled += pending_.keyframesCulled;
    pending_ = {};
    stats_.keyframesProcessed++;
    if (ba.keyframes > 0)
    {
        stats_.baRuns++;
        stats_.baAborted += ba.aborted ? 1 : 0;
        stats_.baWeaklyTiedHeld += static_cast<size_t>(ba.weaklyTiedHeld);
        stats_.baSeconds += baSeconds;
    }
    stats_.totalSeconds += secondsSince(t0);
    MRPT_LOG_DEBUG_FMT("keyframe %lu: BA %d+%d keyframes, %d points, %d outliers, %.1f ms",
                       static_cast<unsigned long>(kf->id()), ba.keyframes, ba.fixedKeyframes,
                       ba.points, ba.outliersRemoved, 1e3 * baSeconds);
}

void LocalMapper::linkNewKeyFrame(const std::shared_ptr<KeyFrame>& kf)
{
    for (size_t i = 0; i < kf->points.size(); ++i)
    {
        const auto mp = kf->points[i];
        if (!mp)
            continue;
        if (mp->isBad())
        {
            kf->points[i].reset();
            continue;
        }
        if (!mp->isObservedBy(kf.get()))
        {
            mp->addObservation(kf.get(), i);
            mp->updateNormalAndDepth();
            mp->computeDistinctiveDescriptor();
        }
        else if (mp->firstKeyFrameId() == kf->id())
        {
            recentPoints_.push_back(mp);  // created by tracking for this keyframe
        }
    }
    kf->updateConnections(params_.covisibility_min_weight);
}

void LocalMapper::cullRecentPoints(const KeyFrame& kf)
{
    for (auto it = recentPoints_.begin(); it != recentPoints_.end();)
    {
        const auto& mp = *it;
        const uint64_t age = kf.id() - mp->firstKeyFrameId();
        const bool weak =
            !mp->isBad() && (mp->foundRatio() < 0.25 || (age >= 2 && mp->numObservations() < 2));
        if (weak)
        {
            mp->setBad();
            pending_.pointsCulled++;
        }
        // Bad, culled, or old enough to have proven itself: no longer "recent".
        if (mp->isBad() || age >= 3)
            it = recentPoints_.erase(it);
        else
            ++it;
    }
}

void LocalMapper::createPointsWithNeighbours(const std::shared_ptr<KeyFrame>& kf)
{
    // Tracking maps a keyframe's close keypoints and only a few beyond close_depth, whose depth
    // alone is too noisy to trust (ORB-SLAM). A far keypoint becomes a point here once a
    // covisible keyframe sees it too, where its depth says it should be (ORB-SLAM's
    // CreateNewMapPoints, searched by projection: the depth predicts where to look); it is
    // placed by triangulation where the two rays see it more sharply than its depth does.
    if (params_.new_point_neighbours <= 0)
        return;
    constexpr double kRadius = 3.0;
    constexpr double kRatio = 0.8;
    const auto neighbours = kf->bestCovisibles(params_.new_point_neighbours);
    const Eigen::Isometry3d T_world_cam = kf->T_cam_world().inverse();
    for (size_t i = 0; i < kf->size(); ++i)
    {
        const bool taken = kf->points[i] && !kf->points[i]->isBad();
        if (taken || !kf->canMap(i) || !kf->features.hasDepth(i))
            continue;
        const auto& p = kf->features.undistorted[i];
        const Eigen::Vector3d p_world =
            T_world_cam * kf->camera.unproject(p.x, p.y, kf->features.depth[i]);
        const int level = kf->features.keypoints[i].octave;
        std::shared_ptr<MapPoint> mp;
        for (KeyFrame* n : neighbours)
        {
            if (n->isBad())
                continue;
            const Eigen::Vector3d& probe = mp ? mp->position_world : p_world;
            const int j =
                matchFreeKeypoint(*n, probe, level, kf->features.descriptor(i), kRadius, kRatio);
            if (j < 0)
                continue;
            if (!mp)
            {
                const Eigen::Vector3d position =
                    twoViewPosition(*kf, i, *n, static_cast<size_t>(j), p_world);
                if (!agreesWithKeypoint(*kf, i, position) ||
                    !agreesWithKeypoint(*n, static_cast<size_t>(j), position))
                    continue;
                mp = map_.createPoint(position, kf.get());
                mp->addObservation(kf.get(), i);
                kf->points[i] = mp;
                recentPoints_.push_back(mp);
                pending_.pointsFromNeighbours++;
            }
            mp->addObservation(n, static_cast<size_t>(j));
            n->points[static_cast<size_t>(j)] = mp;
        }
        if (mp)
        {
            mp->computeDistinctiveDescriptor();
            mp->updateNormalAndDepth();
        }
    }
}

void LocalMapper::fuseWithNeighbours(const std::shared_ptr<KeyFrame>& kf)
{
    if (params_.fuse_neighbours <= 0)
        return;
    std::vector<KeyFrame*> targets;
    std::set<uint64_t> seen{kf->id()};
    for (KeyFrame* n : kf->bestCovisibles(params_.fuse_neighbours))
    {
        if (n->isBad() || !seen.insert(n->id()).second)
            continue;
        targets.push_back(n);
        for (KeyFrame* n2 : n->bestCovisibles(5))
            if (!n2->isBad() && seen.insert(n2->id()).second)
                targets.push_back(n2);
    }
    constexpr double kFuseRadius = 3.0;
    size_t fused = 0;
    std::vector<std::shared_ptr<MapPoint>> own;
    for (const auto& mp : kf->points)
        if (mp && !mp->isBad())
            own.push_back(mp);
    for (KeyFrame* t : targets)
        fused += static_cast<size_t>(fuse(*t, own, kFuseRadius));
    // Their points into this keyframe.
    std::vector<std::shared_ptr<MapPoint>> theirs;
    std::set<uint64_t> ids;
    for (KeyFrame* t : targets)
        for (const auto& mp : t->points)
            if (mp && !mp->isBad() && ids.insert(mp->id()).second)
                theirs.push_back(mp);
    fused += static_cast<size_t>(fuse(*kf, theirs, kFuseRadius));
    for (const auto& mp : kf->points)
    {
        if (mp && !mp->isBad())
        {
            mp->computeDistinctiveDescriptor();
            mp->updateNormalAndDepth();
        }
    }
    kf->updateConnections(params_.covisibility_min_weight);
    pending_.pointsFused += fused;
}

void LocalMapper::cullKeyFrames(const KeyFrame& kf)
{
    // A keyframe is redundant when most of its close points are seen by at least three other
    // keyframes at the same or a finer scale. The origin of a part (the first keyframe) is never
    // culled.
    for (KeyFrame* k : kf.bestCovisibles())
    {
        if (k->isBad() || k->isPartOrigin() || k == &kf)
            continue;
        int nPoints = 0, redundant = 0;
        for (size_t i = 0; i < k->points.size(); ++i)
        {
            const auto& mp = k->points[i];
            if (!mp || mp->isBad())
                continue;
            const float z = k->features.depth[i];
            if (z <= 0.0F || z > k->closeDepth)
                continue;
            nPoints++;
            if (mp->numObservations() <= 3)
                continue;
            const int level = k->features.keypoints[i].octave;
            int others = 0;
            for (const auto& [id, o] : mp->observations())
            {
                if (o.keyframe == k)
                    continue;
                if (o.keyframe->features.keypoints[o.index].octave <= level + 1 && ++others >= 3)
                    break;
            }
            if (others >= 3)
                redundant++;
        }
        if (nPoints > 0 && redundant > params_.keyframe_redundancy * nPoints)
        {
            std::shared_ptr<KeyFrame> parent;
            for (KeyFrame* c : k->bestCovisibles())
            {
                if (!c->isBad())
                {
                    parent = map_.allKeyFrames().at(c->id());
                    break;
                }
            }
            if (!parent)
                continue;
            k->setBad(parent);
            pending_.keyframesCulled++;
        }
    }
}
}  // namespace smap::slam
