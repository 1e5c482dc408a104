#include "smap/slam/KeyFrame.h"

#include <algorithm>

#include "smap/slam/MapPoint.h"

namespace smap::slam
{
KeyFrame::KeyFrame(uint64_t id, const Frame& frame)
    : camera(frame.camera),
      bf(frame.bf),
      closeDepth(frame.closeDepth),
      features(frame.features),
      grid(frame.grid),
      weights(frame.weights),
      mappable(frame.mappable),
      points(frame.size()),
      thumbnail(frame.thumbnail),
      id_(id),
      frameId_(frame.id),
      timestamp_(frame.timestamp),
      T_cam_world_(frame.T_cam_world)
{
}

std::vector<size_t> KeyFrame::keypointsWithPoints() const
{
    std::vector<size_t> out;
    for (size_t i = 0; i < points.size(); ++i)
        if (points[i] && !points[i]->isBad())
            out.push_back(i);
    return out;
}

int KeyFrame::trackedPoints(int min_observations) const
{
    int n = 0;
    for (const auto& p : points)
        if (p && !p->isBad() && static_cast<int>(p->numObservations()) >= min_observations)
            n++;
    return n;
}

void KeyFrame::updateConnections(int min_weight)
{
    std::map<uint64_t, std::pair<KeyFrame*, int>> counts;
    for (const auto& p : points)
    {
        if (!p || p->isBad())
            continue;
        for (const auto& [kfId, obs] : p->observations())
        {
            if (kfId == id_)
                continue;
            auto& c = counts[kfId];
            c.first = obs.keyframe;
            c.second++;
        }
    }
    if (counts.empty())
        return;
    KeyFrame* best = nullptr;
    int bestWeight = -1;
    for (auto& [kfId, c] : counts)
    {
        if (c.second > bestWeight)
        {
            bestWeight = c.second;
            best = c.first;
        }
        if (c.second >= min_weight)
            c.first->addConnection(this, c.second);
    }
    connections_.clear();
    for (auto& [kfId, c] : counts)
        if (c.second >= min_weight)
            connections_[kfId] = c;
    if (connections_.empty() && best != nullptr)
    {
        connections_[best->id()] = {best, bestWeight};
        best->addConnection(this, bestWeight);
    }
    sortConnections();
}

void KeyFrame::addConnection(KeyFrame* other, int weight)
{
    connections_[other->id()] = {other, weight};
    sortConnections();
}

void KeyFrame::eraseConnection(KeyFrame* other)
{
    if (connections_.erase(other->id()) > 0)
        sortConnections();
}

void KeyFrame::sortConnections()
{
    std::vector<std::pair<KeyFrame*, int>> v;
    for (const auto& [kfId, c] : connections_)
        v.push_back(c);
    std::stable_sort(v.begin(), v.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    ordered_.clear();
    for (const auto& c : v)
        ordered_.push_back(c.first);
}

std::vector<KeyFrame*> KeyFrame::bestCovisibles(int n) const
{
    if (n < 0 || static_cast<size_t>(n) >= ordered_.size())
        return ordered_;
    return {ordered_.begin(), ordered_.begin() + n};
}

int KeyFrame::weight(const KeyFrame* other) const
{
    const auto it = connections_.find(other->id());
    return it == connections_.end() ? 0 : it->second.second;
}

void KeyFrame::setBad(const std::shared_ptr<KeyFrame>& parent)
{
    for (const auto& [kfId, c] : connections_)
        c.first->eraseConnection(this);
    connections_.clear();
    ordered_.clear();
    for (auto& p : points)
    {
        if (p)
            p->eraseObservation(this);
        p.reset();
    }
    parent_ = parent;
    if (parent_)
        T_cam_parent_ = T_cam_world_ * parent_->T_cam_world().inverse();
    bad_ = true;
}

Eigen::Isometry3d KeyFrame::resolvedT_cam_world() const
{
    if (!bad_ || !parent_)
        return T_cam_world_;
    return T_cam_parent_ * parent_->resolvedT_cam_world();
}
}  // namespace smap::slam
