#include "smap/slam/Map.h"

namespace smap::slam
{
std::shared_ptr<KeyFrame> Map::createKeyFrame(const Frame& frame)
{
    auto kf = std::make_shared<KeyFrame>(nextKeyFrameId_++, frame);
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

void Map::removeBad()
{
    for (auto it = points_.begin(); it != points_.end();)
        it = it->second->isBad() ? points_.erase(it) : std::next(it);
    for (auto it = keyframes_.begin(); it != keyframes_.end();)
        it = it->second->isBad() ? keyframes_.erase(it) : std::next(it);
}
}  // namespace smap::slam
