#include "smap/slam/Relocalisation.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <optional>
#include <vector>

#include "smap/features/DescriptorMatcher.h"
#include "smap/features/RotationConsistency.h"
#include "smap/slam/Map.h"
#include "smap/slam/PoseOptimizer.h"
#include "smap/slam/ProjectionSearch.h"

namespace smap::slam
{
namespace
{
int tryKeyFrame(Frame& frame, const KeyFrame& kf, const TrackerParameters& params)
{
    const std::vector<size_t> kfRows = kf.keypointsWithPoints(),
                              frameRows = frame.usableKeypoints();
    if (kfRows.size() < 15 || frameRows.size() < 15)
        return 0;
    auto matches = features::matchWithRatioTest(frame.features.descriptors, kf.features.descriptors,
                                                0.75F, kDescriptorHigh, frameRows, kfRows);
    features::RotationConsistency rot;
    for (size_t k = 0; k < matches.size(); ++k)
        rot.add(k, kf.features.keypoints[matches[k].train].angle,
                frame.features.keypoints[matches[k].query].angle);
    std::vector<bool> drop(matches.size(), false);
    for (size_t k : rot.inconsistent())
        drop[k] = true;
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    std::vector<size_t> which;
    for (size_t k = 0; k < matches.size(); ++k)
    {
        if (drop[k])
            continue;
        const auto& p = kf.points[matches[k].train]->position_world;
        object.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                            static_cast<float>(p.z()));
        image.push_back(frame.features.undistorted[matches[k].query]);
        which.push_back(k);
    }
    if (object.size() < 15)
        return 0;
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    cv::Mat K = frame.camera.cameraMatrix();
    const bool solved = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, 300,
                                           4.0F, 0.99, inliers, cv::SOLVEPNP_EPNP);
    if (!solved || inliers.size() < 10)
        return 0;
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    frame.T_cam_world = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
            frame.T_cam_world.linear()(r, c) = R.at<double>(r, c);
        frame.T_cam_world.translation()(r) = tvec.at<double>(r);
    }
    frame.clearMatches();
    for (int k : inliers)
    {
        const auto& m = matches[which[static_cast<size_t>(k)]];
        frame.points[m.query] = kf.points[m.train];
    }
    int good = optimizePose(frame, params.optimisation_rounds, params.optimisation_iterations);
    if (good < 10)
        return 0;
    frame.discardOutliers();
    const int wanted = params.min_inliers_after_relocalisation;
    if (good < wanted)
    {
        const int more = searchKeyFramePoints(frame, kf, 10.0, kDescriptorHigh);
        if (good + more >= wanted)
        {
            good = optimizePose(frame, params.optimisation_rounds, params.optimisation_iterations);
            if (good > 30 && good < wanted)
            {
                searchKeyFramePoints(frame, kf, 3.0, 64);
                good =
                    optimizePose(frame, params.optimisation_rounds, params.optimisation_iterations);
            }
            frame.discardOutliers();
        }
    }
    return good;
}

/// The keyframes a lost frame tries, in order (see relocaliseFrame).
std::vector<const KeyFrame*> chooseCandidates(const Frame& frame, const Map& map,
                                              const TrackerParameters& params,
                                              const KeyFrame* lastReference, int sweepRound,
                                              std::optional<uint32_t> skipPart)
{
    std::vector<std::pair<double, const KeyFrame*>> ranked;
    for (const auto& [id, kf] : map.keyframes())
        if (!kf->isBad() && (!skipPart || kf->part() != *skipPart))
            ranked.emplace_back(-thumbnailSimilarity(frame.thumbnail, kf->thumbnail), kf.get());
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    const auto n = static_cast<size_t>(params.relocalisation_candidates);
    std::vector<const KeyFrame*> candidates;
    const auto addNew = [&candidates](const KeyFrame* kf)
    {
        if (!kf->isBad() && std::find(candidates.begin(), candidates.end(), kf) == candidates.end())
            candidates.push_back(kf);
    };
    for (size_t c = 0; c < std::min(ranked.size(), n); ++c)
        candidates.push_back(ranked[c].second);
    if (lastReference && !lastReference->isBad())
    {
        addNew(lastReference);
        for (const KeyFrame* kf : lastReference->bestCovisibles(static_cast<int>(n) - 1))
            addNew(kf);
    }
    // The sweep: the next slice of the rest of the ranking, round after round, wrapping.
    if (ranked.size() > n && params.relocalisation_sweep > 0 && sweepRound >= 0)
    {
        const size_t rest = ranked.size() - n;
        const auto sweep = static_cast<size_t>(params.relocalisation_sweep);
        const size_t start = (static_cast<size_t>(sweepRound) * sweep) % rest;
        for (size_t k = 0; k < std::min(sweep, rest); ++k)
            addNew(ranked[n + (start + k) % rest].second);
    }
    return candidates;
}

/// The first candidate that places the frame with enough inliers, and those inliers (else the
/// best count and no keyframe; the frame's matches cleared).
std::pair<int, const KeyFrame*> placeAmong(Frame& frame,
                                           const std::vector<const KeyFrame*>& candidates,
                                           const TrackerParameters& params)
{
    int best = 0;
    for (const KeyFrame* kf : candidates)
    {
        const int good = tryKeyFrame(frame, *kf, params);
        if (good >= params.min_inliers_after_relocalisation)
            return {good, kf};
        best = std::max(best, good);
    }
    frame.clearMatches();
    return {best, nullptr};
}
}  // namespace

int relocaliseFrame(Frame& frame, Map& map, const TrackerParameters& params,
                    const KeyFrame* lastReference, int sweepRound)
{
    return placeAmong(frame,
                      chooseCandidates(frame, map, params, lastReference, sweepRound, std::nullopt),
                      params)
        .first;
}

std::optional<uint32_t> relocaliseInOtherPart(Frame& frame, Map& map,
                                              const TrackerParameters& params, uint32_t part,
                                              int sweepRound)
{
    const auto [good, kf] =
        placeAmong(frame, chooseCandidates(frame, map, params, nullptr, sweepRound, part), params);
    if (!kf)
        return std::nullopt;
    return kf->part();
}
}  // namespace smap::slam
