#include "smap/slam/MapPoint.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "smap/features/DescriptorMatcher.h"
#include "smap/slam/KeyFrame.h"

namespace smap::slam
{
MapPoint::MapPoint(uint64_t id, const Eigen::Vector3d& position, KeyFrame* reference)
    : position_world(position),
      id_(id),
      firstKeyFrameId_(reference ? reference->id() : 0),
      reference_(reference)
{
}

void MapPoint::addObservation(KeyFrame* kf, size_t index)
{
    observations_[kf->id()] = {kf, index};
}

void MapPoint::eraseObservation(KeyFrame* kf)
{
    if (observations_.erase(kf->id()) == 0)
        return;
    if (reference_ == kf)
        reference_ = observations_.empty() ? nullptr : observations_.begin()->second.keyframe;
    if (observations_.size() < 2)
        setBad();
}

bool MapPoint::isObservedBy(const KeyFrame* kf) const
{
    return observations_.count(kf->id()) > 0;
}

void MapPoint::setBad()
{
    bad_ = true;
    auto obs = std::move(observations_);
    observations_.clear();
    for (auto& [kfId, o] : obs)
        if (o.index < o.keyframe->points.size() && o.keyframe->points[o.index].get() == this)
            o.keyframe->points[o.index].reset();
}

void MapPoint::replaceWith(const std::shared_ptr<MapPoint>& other)
{
    if (!other || other.get() == this)
        return;
    auto obs = std::move(observations_);
    observations_.clear();
    for (auto& [kfId, o] : obs)
    {
        if (!other->isObservedBy(o.keyframe))
        {
            o.keyframe->points[o.index] = other;
            other->addObservation(o.keyframe, o.index);
        }
        else
        {
            o.keyframe->points[o.index].reset();
        }
    }
    other->increaseVisible(visible_);
    other->increaseFound(found_);
    other->computeDistinctiveDescriptor();
    bad_ = true;
    replacedBy_ = other;
}

void MapPoint::updateNormalAndDepth()
{
    if (observations_.empty() || bad_)
        return;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (const auto& [kfId, o] : observations_)
        n += (position_world - o.keyframe->centre_world()).normalized();
    normal_ = n.normalized();
    const KeyFrame* ref = reference_ ? reference_ : observations_.begin()->second.keyframe;
    const auto it = observations_.find(ref->id());
    if (it == observations_.end())
        return;
    const double dist = (position_world - ref->centre_world()).norm();
    const int level = ref->features.keypoints[it->second.index].octave;
    const auto& pyr = ref->features.pyramid;
    maxDistance_ = dist * pyr.scale[static_cast<size_t>(level)];
    minDistance_ = maxDistance_ / pyr.scale.back();
}

void MapPoint::computeDistinctiveDescriptor()
{
    std::vector<const uint8_t*> ds;
    for (const auto& [kfId, o] : observations_)
        ds.push_back(o.keyframe->features.descriptor(o.index));
    if (ds.empty())
        return;
    size_t best = 0;
    int bestMedian = 1 << 30;
    std::vector<int> d(ds.size());
    for (size_t i = 0; i < ds.size(); ++i)
    {
        for (size_t j = 0; j < ds.size(); ++j)
            d[j] = features::descriptorDistance(ds[i], ds[j]);
        std::nth_element(d.begin(), d.begin() + static_cast<long>((d.size() - 1) / 2), d.end());
        const int median = d[(d.size() - 1) / 2];
        if (median < bestMedian)
        {
            bestMedian = median;
            best = i;
        }
    }
    std::copy(ds[best], ds[best] + 32, descriptor.begin());
}

int MapPoint::predictLevel(double distance, const features::ScalePyramid& pyramid) const
{
    const double ratio = maxDistance_ / std::max(distance, 1e-6);
    const int level = static_cast<int>(std::ceil(std::log(ratio) / pyramid.logScaleFactor));
    return std::clamp(level, 0, pyramid.levels() - 1);
}
}  // namespace smap::slam
