// Absolute trajectory error (ATE) exactly as TUM's evaluate_ate.py computes it: associate
// estimate and ground truth by timestamp, align the estimate onto the ground truth in closed
// form (SE(3); Sim(3) optional), and take per-pose translation errors.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "smap/core/Trajectory.h"
#include "smap/eval/ErrorStatistics.h"
#include "smap/eval/RigidAlignment.h"

namespace smap::eval
{
struct AteOptions
{
    double maxDifference = 0.02;  ///< s; association tolerance (strict <, as TUM)
    double offset = 0.0;          ///< s; added to the estimate's timestamps
    bool withScale = false;       ///< Sim(3) alignment (monocular-style); SE(3) otherwise
};

struct AtePair
{
    double gtTimestamp = 0.0;
    double estTimestamp = 0.0;
    Eigen::Vector3d gtPosition;          ///< world frame of the ground truth
    Eigen::Vector3d estPositionAligned;  ///< estimate after alignment, same frame
    double error = 0.0;                  ///< |gt - aligned estimate|, metres
};

/// A run of consecutive ground-truth poses (in time order) with no estimate associated: where
/// the tracker had no pose (lost) or the estimate ends early.
struct AteGap
{
    size_t poses = 0;     ///< its length; 0 when every ground-truth pose was paired
    size_t firstRow = 0;  ///< its first ground-truth pose, counted from 0 in time order
    double firstTimestamp = 0.0;
    double lastTimestamp = 0.0;
};

struct AteResult
{
    ErrorStatistics translation;  ///< metres
    size_t pairs = 0;
    size_t groundTruthPoses = 0;
    size_t estimatedPoses = 0;
    double coverage = 0.0;  ///< pairs / ground-truth poses
    Alignment alignment;    ///< maps estimate positions into the ground-truth frame
    /// The longest stretch without a pose: coverage says how many ground-truth poses went
    /// unpaired, this whether they were one outage or many short ones.
    AteGap longestGap;
    std::vector<AtePair> perPose;
};

/// Throws core::InputError when either trajectory is empty, when no timestamps overlap within
/// maxDifference (saying so, with both time ranges), or when fewer than 3 pairs exist.
AteResult computeAte(const core::Trajectory& groundTruth, const core::Trajectory& estimate,
                     const AteOptions& options = {});
}  // namespace smap::eval
