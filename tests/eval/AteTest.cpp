#include <gtest/gtest.h>

#include <random>

#include "TrajectoryHelpers.h"
#include "smap/core/InputError.h"
#include "smap/eval/AbsoluteTrajectoryError.h"

using namespace smap;

TEST(Ate, RigidlyMovedEstimateHasZeroError)
{
    const auto gt = test::curve(300);
    const auto est = test::transformed(gt, mrpt::poses::CPose3D(5, -3, 1, 2.0, 0.3, -0.5));
    const auto r = eval::computeAte(gt, est);
    EXPECT_LT(r.translation.rmse, 1e-9);
    EXPECT_EQ(r.pairs, 300u);
    EXPECT_DOUBLE_EQ(r.coverage, 1.0);
}

TEST(Ate, ConstantOffsetAlongOneAxisIsRemovedButItsNoiseIsNot)
{
    // Estimate = gt + (1, 2, 3) + alternating +-d on z: alignment removes the constant part,
    // the +-d pattern (zero mean, uncorrelated with the path) stays: every error is exactly d.
    auto gt = test::curve(200);
    auto est = gt;
    const double d = 0.05;
    for (size_t i = 0; i < est.size(); i++)
    {
        auto& p = est[i].T_world_cam;
        p.x_incr(1.0);
        p.y_incr(2.0);
        p.z_incr(3.0 + (i % 2 ? d : -d));
    }
    const auto r = eval::computeAte(gt, est);
    EXPECT_NEAR(r.translation.rmse, d, 2e-3);
    EXPECT_NEAR(r.translation.mean, d, 2e-3);
    EXPECT_LT(r.translation.std, 2e-3);
}

TEST(Ate, GaussianNoiseGivesSigmaTimesSqrt3)
{
    auto gt = test::curve(20000);
    auto est = gt;
    std::mt19937 rng(42);
    const double sigma = 0.01;
    std::normal_distribution<double> n(0.0, sigma);
    for (auto& p : est)
    {
        p.T_world_cam.x_incr(n(rng));
        p.T_world_cam.y_incr(n(rng));
        p.T_world_cam.z_incr(n(rng));
    }
    const auto r = eval::computeAte(gt, est);
    EXPECT_NEAR(r.translation.rmse, sigma * std::sqrt(3.0), 0.02 * sigma * std::sqrt(3.0));
    // Chi distribution with 3 dof: mean = sigma * 2 sqrt(2/pi).
    EXPECT_NEAR(r.translation.mean, sigma * 2.0 * std::sqrt(2.0 / M_PI), 0.02 * sigma * 1.6);
}

TEST(Ate, PartialOverlapAndAssociationTolerance)
{
    const auto gt = test::curve(100);
    core::Trajectory est(gt.begin() + 50, gt.end());
    for (auto& p : est)
        p.timestamp += 0.012;  // inside the 0.02 s tolerance, nearest its own
    auto r = eval::computeAte(gt, est);
    EXPECT_EQ(r.pairs, 50u);
    EXPECT_DOUBLE_EQ(r.coverage, 0.5);
    EXPECT_LT(r.translation.rmse, 1e-9);

    for (auto& p : est)
        p.timestamp += 0.009;  // now 0.021 s: only the next gt pose is in reach
    r = eval::computeAte(gt, est);
    EXPECT_EQ(r.pairs, 49u);  // the last estimate has no gt pose left within 0.02 s

    eval::AteOptions o;
    o.offset = -0.021;  // the offset undoes the shift exactly
    r = eval::computeAte(gt, est, o);
    EXPECT_EQ(r.pairs, 50u);
    EXPECT_LT(r.translation.rmse, 1e-9);
}

TEST(Ate, NoOverlapSaysSo)
{
    const auto gt = test::curve(50, 1000.0);
    const auto est = test::curve(50, 2000.0);
    try
    {
        eval::computeAte(gt, est);
        FAIL();
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("do not overlap"), std::string::npos) << e.what();
    }
    EXPECT_THROW(eval::computeAte(gt, {}), core::InputError);
    EXPECT_THROW(eval::computeAte(gt, core::Trajectory(gt.begin(), gt.begin() + 2)),
                 core::InputError);
}

TEST(Ate, Sim3AlignmentRemovesScale)
{
    const auto gt = test::curve(300);
    auto est = gt;
    for (auto& p : est)
    {
        p.T_world_cam.x(0.5 * p.T_world_cam.x());
        p.T_world_cam.y(0.5 * p.T_world_cam.y());
        p.T_world_cam.z(0.5 * p.T_world_cam.z());
    }
    EXPECT_GT(eval::computeAte(gt, est).translation.rmse, 0.05);
    eval::AteOptions o;
    o.withScale = true;
    const auto r = eval::computeAte(gt, est, o);
    EXPECT_LT(r.translation.rmse, 1e-9);
    EXPECT_NEAR(r.alignment.scale, 2.0, 1e-9);
}

TEST(Ate, LongestGapIsTheLongestRunOfGroundTruthWithoutAnEstimate)
{
    // 20 ground-truth poses; the estimate misses rows 3-6 (an outage of four), 10-11 and 19,
    // and is given out of time order: the longest gap is rows 3-6.
    const auto gt = test::curve(20);
    core::Trajectory est;
    for (size_t i = 20; i-- > 0;)
        if (!((i >= 3 && i <= 6) || i == 10 || i == 11 || i == 19))
            est.push_back(gt[i]);
    const auto r = eval::computeAte(gt, est);
    EXPECT_EQ(r.pairs, 13u);
    EXPECT_EQ(r.longestGap.poses, 4u);
    EXPECT_EQ(r.longestGap.firstRow, 3u);
    EXPECT_DOUBLE_EQ(r.longestGap.firstTimestamp, gt[3].timestamp);
    EXPECT_DOUBLE_EQ(r.longestGap.lastTimestamp, gt[6].timestamp);

    const auto full = eval::computeAte(gt, gt);
    EXPECT_EQ(full.longestGap.poses, 0u);
}

TEST(Ate, GapAtTheEndCounts)
{
    // The estimate stops after row 11 of 30: the last 18 poses are one gap.
    const auto gt = test::curve(30);
    const core::Trajectory est(gt.begin(), gt.begin() + 12);
    const auto r = eval::computeAte(gt, est);
    EXPECT_EQ(r.longestGap.poses, 18u);
    EXPECT_EQ(r.longestGap.firstRow, 12u);
    EXPECT_DOUBLE_EQ(r.longestGap.lastTimestamp, gt[29].timestamp);
}
