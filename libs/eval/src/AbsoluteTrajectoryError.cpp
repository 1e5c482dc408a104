#include "smap/eval/AbsoluteTrajectoryError.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <numeric>

#include "TrajectoryAssociation.h"
#include "smap/core/InputError.h"

namespace smap::eval
{
namespace
{
std::string timeRange(const core::Trajectory& t)
{
    const auto [lo, hi] = std::minmax_element(
        t.begin(), t.end(), [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
    return mrpt::format("[%.6f, %.6f]", lo->timestamp, hi->timestamp);
}

/// The longest run of ground-truth poses, in time order, that no pair uses.
AteGap longestUnpairedRun(const core::Trajectory& groundTruth,
                          const std::vector<core::AssociatedPair>& matches)
{
    std::vector<bool> paired(groundTruth.size(), false);
    for (const auto& m : matches)
        paired[m.first] = true;
    std::vector<size_t> order(groundTruth.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&groundTruth](size_t a, size_t b)
                     { return groundTruth[a].timestamp < groundTruth[b].timestamp; });
    AteGap best;
    size_t runStart = 0;
    for (size_t row = 0; row <= order.size(); ++row)
    {
        if (row < order.size() && !paired[order[row]])
            continue;
        if (row - runStart > best.poses)
        {
            best.poses = row - runStart;
            best.firstRow = runStart;
            best.firstTimestamp = groundTruth[order[runStart]].timestamp;
            best.lastTimestamp = groundTruth[order[row - 1]].timestamp;
        }
        runStart = row + 1;
    }
    return best;
}
}  // namespace

AteResult computeAte(const core::Trajectory& groundTruth, const core::Trajectory& estimate,
                     const AteOptions& options)
{
    if (groundTruth.empty())
        throw core::InputError("ATE: the ground-truth trajectory is empty");
    if (estimate.empty())
        throw core::InputError("ATE: the estimated trajectory is empty");

    const auto matches =
        detail::associateTrajectories(groundTruth, estimate, options.maxDifference, options.offset);
    if (matches.empty())
    {
        throw core::InputError(mrpt::format(
            "ATE: no timestamps of the estimate (%s, offset %g s) lie within %g s of the ground "
            "truth (%s): the trajectories do not overlap",
            timeRange(estimate).c_str(), options.offset, options.maxDifference,
            timeRange(groundTruth).c_str()));
    }
    if (matches.size() < 3)
    {
        throw core::InputError(mrpt::format(
            "ATE: only %zu pose pair(s) associated; alignment needs at least 3", matches.size()));
    }

    Eigen::Matrix3Xd gtPts(3, matches.size()), estPts(3, matches.size());
    for (size_t k = 0; k < matches.size(); k++)
    {
        const auto& g = groundTruth[matches[k].first].T_world_cam;
        const auto& e = estimate[matches[k].second].T_world_cam;
        gtPts.col(static_cast<Eigen::Index>(k)) = Eigen::Vector3d(g.x(), g.y(), g.z());
        estPts.col(static_cast<Eigen::Index>(k)) = Eigen::Vector3d(e.x(), e.y(), e.z());
    }

    AteResult r;
    r.alignment = alignPoints(estPts, gtPts, options.withScale);
    std::vector<double> errors;
    errors.reserve(matches.size());
    for (size_t k = 0; k < matches.size(); k++)
    {
        AtePair p;
        p.gtTimestamp = groundTruth[matches[k].first].timestamp;
        p.estTimestamp = estimate[matches[k].second].timestamp;
        p.gtPosition = gtPts.col(static_cast<Eigen::Index>(k));
        p.estPositionAligned = r.alignment.apply(estPts.col(static_cast<Eigen::Index>(k)));
        p.error = (p.gtPosition - p.estPositionAligned).norm();
        errors.push_back(p.error);
        r.perPose.push_back(p);
    }
    r.translation = computeStatistics(errors);
    r.pairs = matches.size();
    r.groundTruthPoses = groundTruth.size();
    r.estimatedPoses = estimate.size();
    r.coverage = static_cast<double>(r.pairs) / static_cast<double>(r.groundTruthPoses);
    r.longestGap = longestUnpairedRun(groundTruth, matches);
    return r;
}
}  // namespace smap::eval
