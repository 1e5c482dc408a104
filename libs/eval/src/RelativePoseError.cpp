#include "smap/eval/RelativePoseError.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>

#include "TrajectoryAssociation.h"
#include "smap/core/InputError.h"

namespace smap::eval
{
namespace
{
double rotationAngleDeg(const mrpt::poses::CPose3D& p)
{
    // atan2 of sine and cosine stays accurate near 0, where acos((trace - 1) / 2) loses digits.
    const auto R = p.getRotationMatrix();
    const double s =
        0.5 * std::sqrt(std::pow(R(2, 1) - R(1, 2), 2) + std::pow(R(0, 2) - R(2, 0), 2) +
                        std::pow(R(1, 0) - R(0, 1), 2));
    const double c = 0.5 * (R(0, 0) + R(1, 1) + R(2, 2) - 1.0);
    return std::atan2(s, c) * 180.0 / M_PI;
}
}  // namespace

DeltaUnit parseDeltaUnit(const std::string& s)
{
    if (s == "frames" || s == "f" || s == "frame")
        return DeltaUnit::Frames;
    if (s == "s" || s == "seconds" || s == "second")
        return DeltaUnit::Seconds;
    throw core::InputError(mrpt::format("delta unit '%s' is not 'frames' or 's'", s.c_str()));
}

std::string toString(DeltaUnit u)
{
    return u == DeltaUnit::Frames ? "frames" : "s";
}

RpeResult computeRpe(const core::Trajectory& groundTruth, const core::Trajectory& estimate,
                     const RpeOptions& options)
{
    if (!(options.delta > 0.0))
        throw core::InputError(mrpt::format("RPE: delta = %g must be > 0", options.delta));
    if (options.unit == DeltaUnit::Frames && options.delta != std::floor(options.delta))
        throw core::InputError(
            mrpt::format("RPE: delta = %g frames must be a whole number", options.delta));
    if (groundTruth.empty() || estimate.empty())
        throw core::InputError("RPE: a trajectory is empty");

    auto matches =
        detail::associateTrajectories(groundTruth, estimate, options.maxDifference, options.offset);
    if (matches.size() < 2)
        throw core::InputError(
            mrpt::format("RPE: only %zu pose(s) of the estimate lie within %g s of the ground "
                         "truth: the trajectories do not overlap",
                         matches.size(), options.maxDifference));
    std::sort(matches.begin(), matches.end(),
              [&](const auto& a, const auto& b)
              { return groundTruth[a.first].timestamp < groundTruth[b.first].timestamp; });
    std::vector<double> times;
    times.reserve(matches.size());
    for (const auto& m : matches)
        times.push_back(groundTruth[m.first].timestamp);

    const double gapTolerance = std::max(options.maxDifference, 0.05 * options.delta);
    std::vector<double> transErr, rotErr;
    for (size_t i = 0; i < matches.size(); i++)
    {
        size_t j = 0;
        if (options.unit == DeltaUnit::Frames)
        {
            j = i + static_cast<size_t>(options.delta);
            if (j >= matches.size())
                break;
        }
        else
        {
            const double target = times[i] + options.delta;
            auto it = std::lower_bound(times.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                                       times.end(), target);
            size_t best = static_cast<size_t>(it - times.begin());
            if (best > i + 1 &&
                (best == times.size() || target - times[best - 1] < times[best] - target))
                best--;
            if (best >= times.size())
                break;
            if (std::abs((times[best] - times[i]) - options.delta) > gapTolerance)
                continue;
            j = best;
        }
        const auto& Gi = groundTruth[matches[i].first].T_world_cam;
        const auto& Gj = groundTruth[matches[j].first].T_world_cam;
        const auto& Pi = estimate[matches[i].second].T_world_cam;
        const auto& Pj = estimate[matches[j].second].T_world_cam;
        const mrpt::poses::CPose3D relGt = Gj - Gi;  // Gi^-1 Gj
        const mrpt::poses::CPose3D relEst = Pj - Pi;
        const mrpt::poses::CPose3D err = relEst - relGt;  // relGt^-1 relEst
        transErr.push_back(std::sqrt(err.x() * err.x() + err.y() * err.y() + err.z() * err.z()));
        rotErr.push_back(rotationAngleDeg(err));
    }
    if (transErr.empty())
        throw core::InputError(
            mrpt::format("RPE: no interval of %g %s fits in the %zu associated poses",
                         options.delta, toString(options.unit).c_str(), matches.size()));
    RpeResult r;
    r.translation = computeStatistics(transErr);
    r.rotation = computeStatistics(rotErr);
    r.pairs = transErr.size();
    r.associated = matches.size();
    return r;
}
}  // namespace smap::eval
