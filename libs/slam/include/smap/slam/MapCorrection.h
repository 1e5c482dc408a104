// How a correction computed on a snapshot of the map (a loop's pose graph, a global bundle
// adjustment) reaches the whole map. Tracking goes on while the correction is computed, so the
// map may by then hold keyframes and points the snapshot did not: they follow the snapshot's
// newest keyframe, as the camera that made them was tracked against it.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <set>

namespace smap::slam
{
class Map;

/// Per keyframe id, how a correction moved it: T_cam_world_new = T_cam_world_old * C.
using KeyFrameCorrections = std::map<uint64_t, Eigen::Isometry3d>;

/// The corrections of keyframes whose snapshot pose was `old` and is now `corrected` (both
/// keyed by keyframe id; ids in `old` without a corrected pose are left out).
KeyFrameCorrections correctionsBetween(const std::map<uint64_t, Eigen::Isometry3d>& old,
                                       const std::map<uint64_t, Eigen::Isometry3d>& corrected);

/// Every keyframe of the map moved by its correction; one absent from `C` (created while the
/// correction was computed) by the correction of the newest keyframe in `C`. Every point not in
/// `placed` (ids of points the correction already put in place) moved with the keyframe that
/// first observed it. Hold the map mutex; `C` must not be empty.
void applyCorrections(Map& map, const KeyFrameCorrections& C,
                      const std::set<uint64_t>& placed = {});
}  // namespace smap::slam
