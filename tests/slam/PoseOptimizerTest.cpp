// Motion-only BA on synthetic correspondences: exact recovery from a perturbed start, and
// outliers flagged rather than followed.
#include <gtest/gtest.h>

#include <random>

#include "smap/slam/Frame.h"
#include "smap/slam/Map.h"
#include "smap/slam/PoseOptimizer.h"

using namespace smap;

namespace
{
struct Scenario
{
    slam::Map map;
    slam::Frame frame;
    Eigen::Isometry3d T_true;
};

void build(Scenario& s, int n, double outlier_fraction, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(-2, 2), uz(1.5, 5), unit(0, 1);
    s.frame.camera.width = 640;
    s.frame.camera.height = 480;
    s.frame.camera.fx = s.frame.camera.fy = 525;
    s.frame.camera.cx = 319.5;
    s.frame.camera.cy = 239.5;
    s.frame.bf = 0.08 * 525;
    s.frame.features.pyramid = features::ScalePyramid::make(8, 1.2);
    s.T_true = Eigen::Isometry3d::Identity();
    s.T_true.linear() =
        Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, 1.0, 0.1).normalized()).toRotationMatrix();
    s.T_true.translation() = Eigen::Vector3d(0.3, -0.1, 0.5);
    for (int i = 0; i < n; ++i)
    {
        // A point in front of the true camera, expressed in the world.
        const Eigen::Vector3d p_cam(ux(rng), ux(rng) * 0.7, uz(rng));
        Eigen::Vector2d uv = s.frame.camera.project(p_cam);
        if (uv.x() < 0 || uv.y() < 0 || uv.x() >= 640 || uv.y() >= 480)
            continue;
        const bool outlier = unit(rng) < outlier_fraction;
        if (outlier)
            uv += Eigen::Vector2d(40, -30);
        cv::KeyPoint kp(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31);
        kp.octave = i % 3;
        s.frame.features.keypoints.push_back(kp);
        s.frame.features.undistorted.push_back(kp.pt);
        s.frame.features.depth.push_back(static_cast<float>(p_cam.z()));
        s.frame.features.rightU.push_back(static_cast<float>(uv.x() - s.frame.bf / p_cam.z()));
        s.frame.points.push_back(s.map.createPoint(s.T_true.inverse() * p_cam, nullptr));
        s.frame.outlier.push_back(false);
    }
    s.frame.weights.assign(s.frame.size(), 1.0F);
}

/// Starts the optimiser from the true pose moved by `dt` and turned by `angle` about `axis`.
void startNearTruth(Scenario& s, const Eigen::Vector3d& dt, double angle,
                    const Eigen::Vector3d& axis)
{
    s.frame.T_cam_world = s.T_true;
    s.frame.T_cam_world.translation() += dt;
    s.frame.T_cam_world.linear() =
        s.frame.T_cam_world.linear() * Eigen::AngleAxisd(angle, axis.normalized());
}

/// Every match an inlier, the pose within 0.1 mm and 1e-5 rad of the truth.
void expectTruthWithEveryInlier(const Scenario& s, int inliers)
{
    EXPECT_EQ(inliers, static_cast<int>(s.frame.size()));
    EXPECT_LT((s.frame.T_cam_world.translation() - s.T_true.translation()).norm(), 1e-4);
    EXPECT_LT(
        Eigen::AngleAxisd(s.frame.T_cam_world.linear().transpose() * s.T_true.linear()).angle(),
        1e-5);
}
}  // namespace

TEST(PoseOptimizer, RecoversTheTruePoseFromAPerturbedStart)
{
    Scenario s;
    build(s, 200, 0.0, 1);
    startNearTruth(s, Eigen::Vector3d(0.05, -0.03, 0.04), 0.03, Eigen::Vector3d::UnitZ());
    expectTruthWithEveryInlier(s, slam::optimizePose(s.frame, 4, 10));
}

TEST(PoseOptimizer, FlagsOutliersAndIgnoresThem)
{
    Scenario s;
    build(s, 300, 0.2, 2);
    s.frame.T_cam_world = s.T_true;
    s.frame.T_cam_world.translation() += Eigen::Vector3d(0.02, 0.02, -0.02);
    slam::optimizePose(s.frame, 4, 10);
    EXPECT_LT((s.frame.T_cam_world.translation() - s.T_true.translation()).norm(), 1e-3);
    // Exactly the shifted observations are flagged.
    int wrong = 0;
    for (size_t i = 0; i < s.frame.size(); ++i)
    {
        const Eigen::Vector2d uv =
            s.frame.camera.project(s.T_true * s.frame.points[i]->position_world);
        const bool shifted = (uv - Eigen::Vector2d(s.frame.features.undistorted[i].x,
                                                   s.frame.features.undistorted[i].y))
                                 .norm() > 1.0;
        wrong += shifted != s.frame.outlier[i] ? 1 : 0;
    }
    EXPECT_EQ(wrong, 0);
}

TEST(PoseOptimizer, ZeroWeightObservationsAreIgnored)
{
    Scenario s;
    build(s, 100, 0.5, 3);
    // Weight zero on every shifted observation: the result equals the truth.
    for (size_t i = 0; i < s.frame.size(); ++i)
    {
        const Eigen::Vector2d uv =
            s.frame.camera.project(s.T_true * s.frame.points[i]->position_world);
        if ((uv -
             Eigen::Vector2d(s.frame.features.undistorted[i].x, s.frame.features.undistorted[i].y))
                .norm() > 1.0)
            s.frame.weights[i] = 0.0F;
    }
    s.frame.T_cam_world = Eigen::Isometry3d::Identity();
    slam::optimizePose(s.frame, 4, 20);
    EXPECT_LT((s.frame.T_cam_world.translation() - s.T_true.translation()).norm(), 1e-4);
}

TEST(PoseOptimizer, RecoversThePoseWhenHalfTheKeypointsHaveNoDepth)
{
    Scenario s;
    build(s, 200, 0.0, 4);
    // Every other keypoint without depth: a pixel-only (2-row) observation.
    for (size_t i = 0; i < s.frame.size(); i += 2)
        s.frame.features.depth[i] = -1.0F;
    startNearTruth(s, Eigen::Vector3d(-0.08, 0.05, 0.1), 0.06, Eigen::Vector3d(1, -1, 0.5));
    expectTruthWithEveryInlier(s, slam::optimizePose(s.frame, 4, 10));
}

TEST(PoseOptimizer, AMatchBehindTheCameraIsAnOutlier)
{
    Scenario s;
    build(s, 100, 0.0, 5);
    // The first match's map point moved behind the true camera.
    const Eigen::Vector3d behind_cam(0.1, 0.1, -2.0);
    s.frame.points[0] = s.map.createPoint(s.T_true.inverse() * behind_cam, nullptr);
    s.frame.T_cam_world = s.T_true;
    const int inliers = slam::optimizePose(s.frame, 4, 10);
    EXPECT_TRUE(s.frame.outlier[0]);
    EXPECT_EQ(inliers, static_cast<int>(s.frame.size()) - 1);
    EXPECT_LT((s.frame.T_cam_world.translation() - s.T_true.translation()).norm(), 1e-6);
}
