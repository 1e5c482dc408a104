#include "smap/slam/MapCorrection.h"

#include "smap/slam/Map.h"

namespace smap::slam
{
KeyFrameCorrections correctionsBetween(const std::map<uint64_t, Eigen::Isometry3d>& old,
                                       const std::map<uint64_t, Eigen::Isometry3d>& corrected)
{
    KeyFrameCorrections C;
    for (const auto& [id, T] : corrected)
    {
        const auto o = old.find(id);
        if (o != old.end())
            C[id] = o->second.inverse() * T;
    }
    return C;
}

void applyCorrections(Map& map, const KeyFrameCorrections& C, const std::set<uint64_t>& placed)
{
    const Eigen::Isometry3d& newest = C.rbegin()->second;
    const auto correctionOf = [&](uint64_t id) -> const Eigen::Isometry3d&
    {
        const auto c = C.find(id);
        return c != C.end() ? c->second : newest;
    };
    for (const auto& [id, kf] : map.keyframes())
        kf->setPose(kf->T_cam_world() * correctionOf(id));
    for (const auto& [id, mp] : map.points())
    {
        if (mp->isBad() || mp->observations().empty() || placed.count(id))
            continue;
        // T_cam_world_new = T_cam_world_old * C: a point keeps its place in the camera's frame.
        mp->position_world =
            correctionOf(mp->observations().begin()->first).inverse() * mp->position_world;
    }
}
}  // namespace smap::slam
