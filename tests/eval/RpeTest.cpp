#include <gtest/gtest.h>

#include "TrajectoryHelpers.h"
#include "smap/core/InputError.h"
#include "smap/eval/RelativePoseError.h"

using namespace smap;

namespace
{
core::Trajectory still(size_t n)
{
    core::Trajectory t;
    for (size_t i = 0; i < n; i++)
        t.push_back({static_cast<double>(i) / 10.0, mrpt::poses::CPose3D()});
    return t;
}
}  // namespace

TEST(Rpe, IdenticalTrajectoriesHaveZeroError)
{
    const auto gt = test::curve(200);
    const auto r =
        eval::computeRpe(gt, test::transformed(gt, mrpt::poses::CPose3D(1, 2, 3, 0.4, 0.1, 0.2)));
    EXPECT_LT(r.translation.max, 1e-9);
    EXPECT_LT(r.rotation.max, 1e-6);
    EXPECT_GT(r.pairs, 150u);
}

TEST(Rpe, ConstantVelocityDriftGivesItsRate)
{
    // Ground truth stands still; the estimate drifts 0.2 m/s along x and yaws 10 deg/s.
    const auto gt = still(51);  // 10 Hz, 5 s
    auto est = gt;
    for (auto& p : est)
        p.T_world_cam =
            mrpt::poses::CPose3D(0.2 * p.timestamp, 0, 0, mrpt::DEG2RAD(10.0 * p.timestamp), 0, 0);
    const auto r = eval::computeRpe(gt, est);  // delta 1 s
    EXPECT_EQ(r.pairs, 41u);
    // Over 1 s the estimate moves 0.2 m in its own rotated frame and turns 10 degrees.
    EXPECT_NEAR(r.translation.rmse, 0.2, 1e-9);
    EXPECT_NEAR(r.rotation.rmse, 10.0, 1e-6);

    eval::RpeOptions o;
    o.unit = eval::DeltaUnit::Frames;
    o.delta = 5;
    const auto f = eval::computeRpe(gt, est, o);
    EXPECT_EQ(f.pairs, 46u);
    EXPECT_NEAR(f.translation.rmse, 0.1, 1e-9);
    EXPECT_NEAR(f.rotation.rmse, 5.0, 1e-6);
}

TEST(Rpe, BadOptionsAndNoOverlap)
{
    const auto gt = still(20);
    eval::RpeOptions o;
    o.delta = 0;
    EXPECT_THROW(eval::computeRpe(gt, gt, o), core::InputError);
    o.delta = 10;  // longer than the 1.9 s recording
    EXPECT_THROW(eval::computeRpe(gt, gt, o), core::InputError);
    auto shifted = gt;
    for (auto& p : shifted)
        p.timestamp += 100;
    EXPECT_THROW(eval::computeRpe(gt, shifted), core::InputError);
    EXPECT_EQ(eval::parseDeltaUnit("frames"), eval::DeltaUnit::Frames);
    EXPECT_THROW(eval::parseDeltaUnit("min"), core::InputError);
}
