// Relocalisation of a lost frame: keyframes ranked by thumbnail similarity (then the keyframe
// tracking was lost at and its covisible ones, then a slice of the rest of the ranking that
// moves on from one lost frame to the next), descriptor matches to their map points,
// PnP-RANSAC, then pose refinement and a projection search for more.
#pragma once

#include <cstdint>
#include <optional>

#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
struct Frame;
class KeyFrame;
class Map;

/// Sets frame.T_cam_world and its matches on success. Hold the map mutex. Returns the inlier
/// count of the best candidate (0 when none worked). Candidates: the
/// `relocalisation_candidates` keyframes whose thumbnails look most like the frame's, then
/// `lastReference` (the reference keyframe when tracking was lost; may be null) and as many of
/// its strongest covisible keyframes, the ones already tried left out: after a short outage the
/// camera is most likely back where it was, though a thumbnail taken tens of frames before the
/// loss may look less like the view than an unrelated one does. Then the sweep:
/// `relocalisation_sweep` more keyframes from the rest of the ranking, the slice numbered
/// `sweepRound` (wrapping around; negative: none). The tracker passes the count of frames lost
/// so far, so that a long outage tries every keyframe in turn: a thumbnail of a place seen
/// past a crowd can rank below the crowd's own keyframes, though its points still place the
/// frame.
int relocaliseFrame(Frame& frame, Map& map, const TrackerParameters& params,
                    const KeyFrame* lastReference = nullptr, int sweepRound = -1);

/// Relocalisation among the keyframes of the map's other parts (KeyFrame::part): where a
/// re-anchored part meets the map again. The candidates are those of relocaliseFrame without a
/// last reference, those of `part` left out. On success (frame.T_cam_world set in the other
/// part's frame, with its matches) returns the part the frame was placed in.
std::optional<uint32_t> relocaliseInOtherPart(Frame& frame, Map& map,
                                              const TrackerParameters& params, uint32_t part,
                                              int sweepRound);
}  // namespace smap::slam
