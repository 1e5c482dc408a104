#include "smap/slam/Map.h"

#include <set>

namespace smap::slam
{
std::shared_ptr<KeyFrame> Map::createKeyFrame(const Frame& frame)
{
    auto kf = std::make_shared<KeyFrame>(nextKeyFrameId_++, frame);
    kf->setPartOrigin(kf->id() == 0);  // the world frame; re-anchors mark their own
    keyframes_[kf->id()] = kf;
    all_[kf->id()] = kf;
    return kf;
}

std::shared_ptr<MapPoint> Map::createPoint(const Eigen::Vector3d& position_world,
                                           KeyFrame* reference)
{
    auto p = std::make_shared<MapPoint>(nextPointId_++, position_world, reference);
    points_[p->id()] = p;
    return p;
}

uint32_t Map::newPart()
{
    liveParts_.insert(nextPart_);
    return nextPart_++;
}

void Map::mergePart(uint32_t from, uint32_t to, const Eigen::Isometry3d& T_to_from)
{
    // T_cam_to = T_cam_from * T_from_to. Culled keyframes follow their parents (same part).
    const Eigen::Isometry3d T_from_to = T_to_from.inverse();
    std::set<uint64_t> moved;
    for (const auto& [id, kf] : all_)
    {
        if (kf->part() != from)
            continue;
        kf->setPart(to);
        kf->setPartOrigin(false);
        if (kf->isBad())
            continue;
        kf->setPose(kf->T_cam_world() * T_from_to);
        for (const auto& mp : kf->points)
            if (mp && !mp->isBad() && moved.insert(mp->id()).second)
            {
                mp->position_world = T_to_from * mp->position_world;
                mp->updateNormalAndDepth();
            }
    }
    liveParts_.erase(from);
    ++merged_;
    ++corrections_;
}

void Map::discardPart(uint32_t part)
{
    for (const auto& [id, kf] : keyframes_)
        if (kf->part() == part && !kf->isBad())
            kf->setBad(nullptr);
    liveParts_.erase(part);
    discarded_.insert(part);
    removeBad();
}

void Map::removeBad()
{
    for (auto it = points_.begin(); it != points_.end();)
        it = it->second->isBad() ? points_.erase(it) : std::next(it);
    for (auto it = keyframes_.begin(); it != keyframes_.end();)
        it = it->second->isBad() ? keyframes_.erase(it) : std::next(it);
}
}  // namespace smap::slam
