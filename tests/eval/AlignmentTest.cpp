#include <gtest/gtest.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/LU>
#include <random>

#include "smap/eval/ErrorStatistics.h"
#include "smap/eval/RigidAlignment.h"

using namespace smap::eval;

TEST(ErrorStatistics, KnownAnswers)
{
    const auto s = computeStatistics({1.0, 2.0, 3.0, 4.0});
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
    EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_EQ(s.count, 4u);
    EXPECT_DOUBLE_EQ(computeStatistics({3.0, 1.0, 2.0}).median, 2.0);
    EXPECT_EQ(computeStatistics({}).count, 0u);
}

TEST(RigidAlignment, RecoversAKnownRigidTransform)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2, 2);
    Eigen::Matrix3Xd model(3, 50);
    for (int i = 0; i < 50; i++)
        model.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
    const mrpt::poses::CPose3D T(0.3, -1.2, 2.0, 0.7, -0.4, 1.1);
    const Eigen::Matrix3d R = T.getRotationMatrix().asEigen();
    const Eigen::Matrix3Xd data = (R * model).colwise() + Eigen::Vector3d(0.3, -1.2, 2.0);
    const Alignment a = alignPoints(model, data, false);
    EXPECT_LT((a.R - R).norm(), 1e-12);
    EXPECT_LT((a.t - Eigen::Vector3d(0.3, -1.2, 2.0)).norm(), 1e-12);
    EXPECT_DOUBLE_EQ(a.scale, 1.0);

    const Alignment s = alignPoints(model, 2.5 * data, true);
    EXPECT_NEAR(s.scale, 2.5, 1e-12);
    EXPECT_LT((s.R - R).norm(), 1e-12);
}

TEST(RigidAlignment, NeverReturnsAReflection)
{
    // A mirrored point set: the best proper rotation is not the reflection.
    Eigen::Matrix3Xd model(3, 4), data(3, 4);
    model << 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1;
    data = model;
    data.row(0) *= -1.0;
    const Alignment a = alignPoints(model, data, false);
    EXPECT_NEAR(a.R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((a.R * a.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
}
