#include "LoopDetector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <set>

#include "smap/core/RecordingTime.h"
#include "smap/features/DescriptorMatcher.h"
#include "smap/slam/Frame.h"
#include "smap/slam/Map.h"
#include "smap/slam/PoseOptimizer.h"
#include "smap/slam/ProjectionSearch.h"
#include "smap/slam/RigidRansac.h"

namespace smap::slam
{
namespace
{
constexpr int kRansacIterations = 300;
constexpr double kToleranceDepth = 1.5;    ///< m: beyond, the 3D tolerance grows with depth
constexpr double kProjectionRadius = 4.0;  ///< px at level 0
constexpr int kLoopNeighbours = 10;        ///< covisible keyframes around the loop keyframe
constexpr int kScoreNeighbours = 10;       ///< covisible keyframes that set the score bar
constexpr int kRefineRounds = 4;           ///< motion-only BA rounds (outliers dropped between)
constexpr int kRefineIterations = 10;
}  // namespace

LoopDetector::Outcome LoopDetector::detect(const std::shared_ptr<KeyFrame>& kf, Map& map)
{
    std::vector<size_t> rows;
    bool enoughKeyFrames = false;
    {
        std::lock_guard<std::mutex> lock(map.mutex());
        for (uint64_t id : database_.ids())
            if (map.keyframes().count(id) == 0)
                database_.erase(id);
        if (kf->isBad())
            return {};
        rows = kf->keypointsWithPoints();
        enoughKeyFrames = static_cast<int>(map.keyframes().size()) >= params_.min_keyframes;
    }
    // The query needs no lock: the database is the detector's own, and a keyframe's
    // descriptors never change. Tracking and local mapping go on meanwhile.
    std::vector<KeyFrameDatabase::Score> scores;
    if (enoughKeyFrames)
        scores = database_.query(kf->features.descriptors, rows, kDescriptorLow, 1);
    Outcome out;
    if (!scores.empty())
    {
        std::lock_guard<std::mutex> lock(map.mutex());
        if (!kf->isBad())
            out = verifyCandidates(kf, map, scores);
    }
    database_.add(kf->id(), kf->features.descriptors, rows);
    return out;
}

LoopDetector::Outcome LoopDetector::verifyCandidates(
    const std::shared_ptr<KeyFrame>& kf, const Map& map,
    const std::vector<KeyFrameDatabase::Score>& scores) const
{
    Outcome out;
    for (const auto& [candidate, score] : candidates(*kf, map, scores))
    {
        Check check;
        check.candidateId = candidate->id();
        check.score = score;
        out.match = verify(*kf, *candidate, check);
        out.checks.push_back(check);
        if (out.match)
        {
            out.match->loop = candidate;
            break;
        }
    }
    return out;
}

std::vector<std::pair<std::shared_ptr<KeyFrame>, int>> LoopDetector::candidates(
    const KeyFrame& kf, const Map& map, const std::vector<KeyFrameDatabase::Score>& scores) const
{
    // The bar: a share of the lowest score among the keyframe's strongest neighbours, the
    // places that certainly look like this one.
    double lowest = std::numeric_limits<double>::infinity();
    for (const KeyFrame* c : kf.bestCovisibles(kScoreNeighbours))
    {
        const auto s = std::find_if(scores.begin(), scores.end(),
                                    [&](const auto& x) { return x.keyframeId == c->id(); });
        lowest = std::min(lowest, s == scores.end() ? 0.0 : s->score);
    }
    const double bar = std::isinf(lowest) ? 0.0 : params_.neighbour_score_ratio * lowest;
    std::vector<std::pair<std::shared_ptr<KeyFrame>, int>> out;
    for (const auto& s : scores)
    {
        if (s.score < bar || static_cast<int>(out.size()) >= params_.max_candidates)
            break;
        // Places seen long enough ago, whether or not tracking has linked them to this one
        // already (it does when the drift is small): the recent past is not a loop. Another part
        // of the map is joined by tracking (Map::mergePart), not by a loop.
        const auto it = map.keyframes().find(s.keyframeId);
        if (s.matches < params_.min_matches || it == map.keyframes().end() || it->second->isBad() ||
            !core::reached(kf.timestamp() - it->second->timestamp(), params_.min_age_s) ||
            it->second->part() != kf.part())
            continue;
        out.emplace_back(it->second, s.matches);
    }
    return out;
}

std::optional<LoopMatch> LoopDetector::verify(const KeyFrame& kf, const KeyFrame& candidate,
                                              Check& check) const
{
    std::vector<size_t> kfRows;
    for (size_t i = 0; i < kf.features.size(); ++i)
        if (kf.weights[i] > 0.0F && kf.features.hasDepth(i))
            kfRows.push_back(i);
    const std::vector<size_t> candidateRows = candidate.keypointsWithPoints();
    const auto matches =
        features::matchWithRatioTest(kf.features.descriptors, candidate.features.descriptors, 0.75F,
                                     kDescriptorHigh, kfRows, candidateRows);
    check.descriptorMatches = static_cast<int>(matches.size());
    if (check.descriptorMatches < params_.min_inliers)
        return std::nullopt;
    std::vector<Eigen::Vector3d> world, cam;
    std::vector<double> tolerance;
    for (const auto& m : matches)
    {
        world.push_back(candidate.points[m.train]->position_world);
        const auto& p = kf.features.undistorted[m.query];
        const double z = kf.features.depth[m.query];
        cam.push_back(kf.camera.unproject(p.x, p.y, z));
        // Depth noise grows with distance: the tolerance from 1.5 m on in proportion.
        tolerance.push_back(params_.inlier_distance * std::max(1.0, z / kToleranceDepth));
    }
    const auto rigid = estimateRigidRansac(world, cam, tolerance, 3, kRansacIterations,
                                           static_cast<uint32_t>(kf.id()));
    check.inliers = rigid ? static_cast<int>(rigid->inliers.size()) : 0;
    if (check.inliers < params_.min_inliers)
        return std::nullopt;
    LoopMatch match;
    match.T_cam_world = rigid->T_a_b.inverse();
    match.inliers = check.inliers;
    // The 3D-3D motion rests on a few noisy depths: refined on the reprojections of the whole
    // neighbourhood, twice (the better pose finds more of it).
    for (int round = 0; round < 2; ++round)
        match.projectedMatches = refinePose(kf, match.T_cam_world,
                                            projectNeighbourhood(kf, match.T_cam_world, candidate));
    check.projectedMatches = match.projectedMatches;
    if (match.projectedMatches < params_.min_projected_matches)
        return std::nullopt;
    return match;
}

std::vector<std::pair<size_t, std::shared_ptr<MapPoint>>> LoopDetector::projectNeighbourhood(
    const KeyFrame& kf, const Eigen::Isometry3d& T_cam_world, const KeyFrame& candidate) const
{
    std::vector<const KeyFrame*> around = {&candidate};
    for (const KeyFrame* c : candidate.bestCovisibles(kLoopNeighbours))
        around.push_back(c);
    std::set<uint64_t> seen;
    std::vector<char> taken(kf.features.size(), 0);
    std::vector<std::pair<size_t, std::shared_ptr<MapPoint>>> out;
    for (const KeyFrame* k : around)
    {
        for (const auto& mp : k->points)
        {
            if (!mp || mp->isBad() || !seen.insert(mp->id()).second)
                continue;
            const int j = matchProjectedPoint(kf, T_cam_world, *mp, kProjectionRadius);
            if (j >= 0 && !taken[static_cast<size_t>(j)])
            {
                taken[static_cast<size_t>(j)] = 1;
                out.emplace_back(static_cast<size_t>(j), mp);
            }
        }
    }
    return out;
}

int LoopDetector::refinePose(
    const KeyFrame& kf, Eigen::Isometry3d& T_cam_world,
    const std::vector<std::pair<size_t, std::shared_ptr<MapPoint>>>& matches)
{
    Frame f;
    f.camera = kf.camera;
    f.bf = kf.bf;
    f.closeDepth = kf.closeDepth;
    f.features = kf.features;
    f.weights = kf.weights;
    f.clearMatches();
    for (const auto& [j, mp] : matches)
        f.points[j] = mp;
    f.T_cam_world = T_cam_world;
    const int inliers = optimizePose(f, kRefineRounds, kRefineIterations);
    if (inliers >= 3)
        T_cam_world = f.T_cam_world;
    return inliers;
}
}  // namespace smap::slam
