// Synthetic trajectories for the evaluation tests.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cmath>

#include "smap/core/Trajectory.h"

namespace smap::test
{
/// n poses at 30 Hz along a smooth 3D curve with varying orientation.
inline core::Trajectory curve(size_t n, double t0 = 1000.0)
{
    core::Trajectory t;
    for (size_t i = 0; i < n; i++)
    {
        const double s = static_cast<double>(i) / 30.0;
        t.push_back({t0 + s, mrpt::poses::CPose3D(std::cos(s), std::sin(1.3 * s), 0.3 * s, 0.5 * s,
                                                  0.2 * std::sin(s), 0.1 * s)});
    }
    return t;
}

/// Applies T_new_old on the left of every pose (a change of world frame).
inline core::Trajectory transformed(const core::Trajectory& in, const mrpt::poses::CPose3D& T)
{
    core::Trajectory out = in;
    for (auto& p : out)
        p.T_world_cam = T + p.T_world_cam;
    return out;
}
}  // namespace smap::test
