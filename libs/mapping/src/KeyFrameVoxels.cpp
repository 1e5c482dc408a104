#include "KeyFrameVoxels.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "smap/core/RecordingTime.h"

namespace smap::mapping
{
namespace
{
/// The 27 voxel offsets of a point's neighbourhood.
std::array<std::array<int64_t, 3>, 27> neighbourhood()
{
    std::array<std::array<int64_t, 3>, 27> out{};
    size_t i = 0;
    for (int64_t dx = -1; dx <= 1; ++dx)
    {
        for (int64_t dy = -1; dy <= 1; ++dy)
        {
            for (int64_t dz = -1; dz <= 1; ++dz)
                out[i++] = {dx, dy, dz};
        }
    }
    return out;
}

void addDistinct(std::vector<uint32_t>& keyframes, uint32_t k, size_t atMost)
{
    if (keyframes.size() < atMost &&
        std::find(keyframes.begin(), keyframes.end(), k) == keyframes.end())
        keyframes.push_back(k);
}

/// Adds p to a voxel's clear points unless one lies within `thin` of it.
void addClear(std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& p, double thin)
{
    for (const auto& q : points)
    {
        if ((q - p).squaredNorm() <= thin * thin)
            return;
    }
    points.push_back(p);
}

bool anyWithin(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& p, double r)
{
    return std::any_of(points.begin(), points.end(),
                       [&](const Eigen::Vector3f& q) { return (q - p).squaredNorm() <= r * r; });
}
}  // namespace

KeyFrameVoxels::KeyFrameVoxels(double edge, size_t needed, double span_s, bool needClear)
    : edge_(edge), needed_(needed), span_s_(span_s), needClear_(needClear)
{
}

int64_t KeyFrameVoxels::cell(float a) const
{
    return static_cast<int64_t>(std::floor(a / edge_));
}

void KeyFrameVoxels::add(const Eigen::Vector3f& p, uint32_t keyframe, double time, bool clear)
{
    Seen& s = seen_[voxelKey(cell(p.x()), cell(p.y()), cell(p.z()))];
    addDistinct(s.keyframes, keyframe, needed_);
    s.firstTime = std::min(s.firstTime, time);
    s.lastTime = std::max(s.lastTime, time);
    if (clear && needClear_)  // without the clear test, no query reads them
        addClear(s.clearPoints, p, edge_ / 4.0);
}

bool KeyFrameVoxels::confirmed(const Eigen::Vector3f& p) const
{
    static const auto kNeighbourhood = neighbourhood();
    std::vector<uint32_t> keyframes;
    double first = std::numeric_limits<double>::infinity();
    double last = -first;
    bool clear = !needClear_;
    const int64_t cx = cell(p.x()), cy = cell(p.y()), cz = cell(p.z());
    for (const auto& [dx, dy, dz] : kNeighbourhood)
    {
        const auto it = seen_.find(voxelKey(cx + dx, cy + dy, cz + dz));
        if (it == seen_.end())
            continue;
        for (uint32_t k : it->second.keyframes)
            addDistinct(keyframes, k, needed_);
        first = std::min(first, it->second.firstTime);
        last = std::max(last, it->second.lastTime);
        clear = clear || anyWithin(it->second.clearPoints, p, edge_);
    }
    return clear && keyframes.size() >= needed_ && last >= first &&
           core::reached(last - first, span_s_);
}
}  // namespace smap::mapping
