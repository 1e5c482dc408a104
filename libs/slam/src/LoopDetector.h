// Loop detection for LoopCloser: candidates from the keyframe database, verified with depth.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "smap/slam/KeyFrameDatabase.h"
#include "smap/slam/LoopCorrection.h"
#include "smap/slam/SlamParameters.h"

namespace smap::slam
{
class KeyFrame;
class Map;
class MapPoint;

class LoopDetector
{
public:
    explicit LoopDetector(const LoopClosingParameters& params) : params_(params) {}

    /// What the verification of one candidate found (for the log).
    struct Check
    {
        uint64_t candidateId = 0;
        int score = 0;              ///< database matches
        int descriptorMatches = 0;  ///< ratio-test matches with its map points
        int inliers = 0;            ///< 3D-3D RANSAC
        int projectedMatches = 0;
    };
    struct Outcome
    {
        std::optional<LoopMatch> match;
        std::vector<Check> checks;  ///< one per candidate verified
    };
    /// Looks `kf` up among the keyframes indexed before, verifies the best candidates, then
    /// indexes it (bad keyframes are dropped from the index first). Takes the map mutex itself,
    /// and not for the database query (half of the work).
    Outcome detect(const std::shared_ptr<KeyFrame>& kf, Map& map);

private:
    /// With the map mutex held: the candidates among `scores`, verified best first until one
    /// holds.
    Outcome verifyCandidates(const std::shared_ptr<KeyFrame>& kf, const Map& map,
                             const std::vector<KeyFrameDatabase::Score>& scores) const;
    std::vector<std::pair<std::shared_ptr<KeyFrame>, int>> candidates(
        const KeyFrame& kf, const Map& map,
        const std::vector<KeyFrameDatabase::Score>& scores) const;
    std::optional<LoopMatch> verify(const KeyFrame& kf, const KeyFrame& candidate,
                                    Check& check) const;
    /// The candidate's and its covisible keyframes' points that land on a keypoint of `kf`
    /// seen from `T_cam_world` (one point per keypoint).
    std::vector<std::pair<size_t, std::shared_ptr<MapPoint>>> projectNeighbourhood(
        const KeyFrame& kf, const Eigen::Isometry3d& T_cam_world, const KeyFrame& candidate) const;
    /// Motion-only bundle adjustment of `T_cam_world` on those matches; the inliers.
    static int refinePose(const KeyFrame& kf, Eigen::Isometry3d& T_cam_world,
                          const std::vector<std::pair<size_t, std::shared_ptr<MapPoint>>>& matches);

    LoopClosingParameters params_;
    KeyFrameDatabase database_;
};
}  // namespace smap::slam
