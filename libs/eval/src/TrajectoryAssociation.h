// Association of an estimated trajectory with its ground truth (shared by ATE and RPE).
#pragma once

#include <vector>

#include "smap/core/TimestampAssociation.h"
#include "smap/core/Trajectory.h"

namespace smap::eval::detail
{
/// Pairs (first = ground-truth index, second = estimate index), TUM-style.
inline std::vector<core::AssociatedPair> associateTrajectories(const core::Trajectory& groundTruth,
                                                               const core::Trajectory& estimate,
                                                               double maxDifference, double offset)
{
    std::vector<double> tGt, tEst;
    tGt.reserve(groundTruth.size());
    tEst.reserve(estimate.size());
    for (const auto& p : groundTruth)
        tGt.push_back(p.timestamp);
    for (const auto& p : estimate)
        tEst.push_back(p.timestamp);
    return core::associateTimestamps(tGt, tEst, maxDifference, offset);
}
}  // namespace smap::eval::detail
