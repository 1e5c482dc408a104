// Relative pose error (RPE), following TUM's evaluate_rpe.py: the drift of the estimate over a
// fixed interval, independent of global alignment.
#pragma once

#include <string>

#include "smap/core/Trajectory.h"
#include "smap/eval/ErrorStatistics.h"

namespace smap::eval
{
enum class DeltaUnit
{
    Frames,   ///< interval = delta associated poses later
    Seconds,  ///< interval = the associated pose closest to delta seconds later
};

struct RpeOptions
{
    double delta = 1.0;
    DeltaUnit unit = DeltaUnit::Seconds;
    double maxDifference = 0.02;  ///< s; gt/estimate association tolerance
    double offset = 0.0;          ///< s; added to the estimate's timestamps
};

struct RpeResult
{
    ErrorStatistics translation;  ///< metres per interval
    ErrorStatistics rotation;     ///< degrees per interval
    size_t pairs = 0;             ///< intervals evaluated
    size_t associated = 0;        ///< gt/estimate poses associated
};

/// For associated poses i and j (j one interval after i):
///   E_ij = (G_i^-1 G_j)^-1 (P_i^-1 P_j), translation error |t(E_ij)|, rotation error angle(E_ij).
/// With DeltaUnit::Seconds, j is the associated pose whose time is closest to t_i + delta; an
/// interval whose duration differs from delta by more than max(maxDifference, 5% of delta) (a
/// gap in the data, or the end of the recording) is skipped. Throws core::InputError when nothing
/// overlaps or no interval fits.
RpeResult computeRpe(const core::Trajectory& groundTruth, const core::Trajectory& estimate,
                     const RpeOptions& options = {});

DeltaUnit parseDeltaUnit(const std::string& s);  ///< "frames"/"f" or "s"/"seconds"
std::string toString(DeltaUnit u);
}  // namespace smap::eval
