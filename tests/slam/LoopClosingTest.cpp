// Loop closing's parts on known answers: the keyframe descriptor index finds the keyframe whose
// descriptors a query nearly copies, 3D-3D RANSAC recovers a known motion among outliers, and
// the pose graph spreads a loop's drift so that the lap closes.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <random>

#include "KeyFrameFixtures.h"
#include "smap/core/InputError.h"
#include "smap/slam/KeyFrameDatabase.h"
#include "smap/slam/LoopCorrection.h"
#include "smap/slam/Map.h"
#include "smap/slam/PoseGraph.h"
#include "smap/slam/RigidRansac.h"
#include "smap/slam/SlamParameters.h"

using namespace smap;

namespace
{
cv::Mat randomDescriptors(int n, std::mt19937& rng)
{
    cv::Mat d(n, 32, CV_8UC1);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < 32; ++c)
            d.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng));
    return d;
}

/// `d` with `bits` random bits of every row flipped.
cv::Mat flipBits(const cv::Mat& d, int bits, std::mt19937& rng)
{
    cv::Mat out = d.clone();
    std::uniform_int_distribution<int> bit(0, 255);
    for (int r = 0; r < out.rows; ++r)
        for (int k = 0; k < bits; ++k)
        {
            const int b = bit(rng);
            out.at<uint8_t>(r, b / 8) ^= static_cast<uint8_t>(1U << (b % 8));
        }
    return out;
}

std::vector<size_t> allRows(int n)
{
    std::vector<size_t> rows(static_cast<size_t>(n));
    for (size_t i = 0; i < rows.size(); ++i)
        rows[i] = i;
    return rows;
}

Eigen::Isometry3d pose(double yaw, double pitch, const Eigen::Vector3d& t)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = t;
    return T;
}

double angleDeg(const Eigen::Isometry3d& T)
{
    return Eigen::AngleAxisd(T.rotation()).angle() * 180.0 / M_PI;
}
}  // namespace

TEST(KeyFrameDatabase, FindsTheKeyFrameAQueryNearlyCopies)
{
    std::mt19937 rng(3);
    slam::KeyFrameDatabase db;
    std::vector<cv::Mat> kfs;
    for (uint64_t id = 0; id < 6; ++id)
    {
        kfs.push_back(randomDescriptors(400, rng));
        db.add(id, kfs.back(), allRows(400));
    }
    // Half of keyframe 4's descriptors seen again with 20 of 256 bits changed, among as many
    // unrelated ones.
    cv::Mat query;
    cv::vconcat(flipBits(kfs[4].rowRange(0, 200), 20, rng), randomDescriptors(200, rng), query);
    const auto scores = db.query(query, allRows(400), 50, 1);
    ASSERT_FALSE(scores.empty());
    EXPECT_EQ(scores[0].keyframeId, 4U);
    EXPECT_GE(scores[0].matches, 170);  // 20 flipped bits share a chunk with p > 0.9
    for (size_t k = 1; k < scores.size(); ++k)
        EXPECT_LT(scores[k].matches, 5) << "keyframe " << scores[k].keyframeId;
    // Excluded, or erased, it is not found; the threshold drops the weak ones.
    const auto without = db.query(query, allRows(400), 50, 1, {4});
    EXPECT_TRUE(without.empty() || without[0].matches < 5);
    EXPECT_TRUE(db.query(query, allRows(400), 50, 10, {4}).empty());
    db.erase(4);
    EXPECT_FALSE(db.contains(4));
    EXPECT_EQ(db.ids(), (std::vector<uint64_t>{0, 1, 2, 3, 5}));
    EXPECT_TRUE(db.query(query, allRows(400), 50, 10).empty());
}

// A pattern every keyframe shows (a repeated texture) counts for little: the keyframe that
// shares fewer but rarer descriptors with the query ranks first.
TEST(KeyFrameDatabase, RareDescriptorsOutweighCommonOnes)
{
    std::mt19937 rng(9);
    const cv::Mat common = randomDescriptors(150, rng), unique = randomDescriptors(60, rng);
    slam::KeyFrameDatabase db;
    for (uint64_t id = 0; id < 8; ++id)
    {
        cv::Mat d;
        cv::vconcat(common, randomDescriptors(200, rng), d);
        if (id == 5)
            cv::vconcat(d, unique, d);
        db.add(id, d, allRows(d.rows));
    }
    cv::Mat query;
    cv::vconcat(common, unique, query);
    const auto scores = db.query(query, allRows(query.rows), 50, 1);
    ASSERT_EQ(scores.size(), 8U);
    EXPECT_EQ(scores[0].keyframeId, 5U);
    EXPECT_EQ(scores[0].matches, 210);
    EXPECT_EQ(scores[1].matches, 150);
    EXPECT_NEAR(scores[1].score, 0.0, 1e-9);  // held by all eight: log(8 / 8)
    EXPECT_NEAR(scores[0].score, 60 * std::log(8.0), 1e-6);
}

TEST(KeyFrameDatabase, IndexesOnlyTheGivenRows)
{
    std::mt19937 rng(5);
    slam::KeyFrameDatabase db;
    const cv::Mat d = randomDescriptors(100, rng);
    db.add(7, d, {10, 11, 12});
    const auto scores = db.query(d, allRows(100), 0, 1);
    ASSERT_EQ(scores.size(), 1U);
    EXPECT_EQ(scores[0].matches, 3);
    EXPECT_THROW(db.add(8, cv::Mat(3, 16, CV_8UC1), {0}), std::invalid_argument);
}

TEST(RigidRansac, RecoversAKnownMotionAmongOutliers)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(-2.0, 2.0), noise(-0.005, 0.005);
    const Eigen::Isometry3d T_a_b = pose(0.4, -0.2, {0.3, -1.2, 0.8});
    std::vector<Eigen::Vector3d> a, b;
    for (int k = 0; k < 120; ++k)
    {
        const Eigen::Vector3d p(coord(rng), coord(rng), 3.0 + coord(rng));
        b.push_back(p);
        // Every third pair is a wrong match.
        a.push_back(k % 3 == 0 ? Eigen::Vector3d(coord(rng), coord(rng), coord(rng))
                               : T_a_b * p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    }
    const std::vector<double> tol(a.size(), 0.03);
    const auto e = slam::estimateRigidRansac(a, b, tol, 40, 300, 1);
    ASSERT_TRUE(e.has_value());
    EXPECT_LT((e->T_a_b.translation() - T_a_b.translation()).norm(), 0.005);
    EXPECT_LT(angleDeg(e->T_a_b.inverse() * T_a_b), 0.3);
    EXPECT_EQ(e->inliers.size(), 80U);
    for (size_t k : e->inliers)
        EXPECT_NE(k % 3, 0U) << "outlier " << k << " taken as an inlier";
    // The same seed gives the same answer; too few inliers gives none.
    const auto again = slam::estimateRigidRansac(a, b, tol, 40, 300, 1);
    EXPECT_TRUE(again->T_a_b.isApprox(e->T_a_b));
    EXPECT_FALSE(slam::estimateRigidRansac(a, b, tol, 100, 300, 1).has_value());
    EXPECT_FALSE(slam::estimateRigidRansac({a[0], a[1]}, {b[0], b[1]}, {0.03, 0.03}, 2, 10, 1));
    // A pair's own tolerance: the far pairs, 10 cm off, count only when theirs allows it.
    auto far = a;
    std::vector<double> tight(a.size(), 0.03), loose(a.size(), 0.03);
    for (size_t k = 1; k < far.size(); k += 3)
    {
        far[k] += Eigen::Vector3d(0.1, 0.0, 0.0);
        loose[k] = 0.15;
    }
    EXPECT_LT(slam::estimateRigidRansac(far, b, tight, 10, 300, 1)->inliers.size(), 60U);
    EXPECT_EQ(slam::estimateRigidRansac(far, b, loose, 10, 300, 1)->inliers.size(), 80U);
}

// A lap of 24 keyframes on a 4 m circle. Odometry edges carry a bias (each step turns 0.4 deg
// and moves 1 cm too far), the loop edge is exact. Chained, the last keyframe ends up tens of
// centimetres off; the optimised graph closes the lap.
TEST(PoseGraph, LoopEdgeTakesOutTheDriftOfALap)
{
    const int n = 24;
    std::vector<Eigen::Isometry3d> truth;  // T_cam_world
    for (int k = 0; k < n; ++k)
    {
        const double a = 2.0 * M_PI * k / n;
        truth.push_back(
            pose(-a, 0.0, {2.0 * std::sin(a), 0.1 * std::sin(3 * a), 2.0 * std::cos(a)}).inverse());
    }
    const Eigen::Isometry3d bias = pose(0.4 * M_PI / 180.0, 0.0, {0.01, 0.0, 0.0});
    std::vector<slam::PoseGraphEdge> edges;
    std::map<uint64_t, Eigen::Isometry3d> poses{{0, truth[0]}};
    for (int k = 1; k < n; ++k)
    {
        const Eigen::Isometry3d T_prev_k = truth[k - 1] * truth[k].inverse() * bias;
        edges.push_back({static_cast<uint64_t>(k - 1), static_cast<uint64_t>(k), T_prev_k, 1.0});
        poses[k] = T_prev_k.inverse() * poses[k - 1];  // chained odometry
    }
    const auto err = [&](uint64_t k)
    { return (poses[k].inverse().translation() - truth[k].inverse().translation()).norm(); };
    const double before = err(n - 1);
    ASSERT_GT(before, 0.15);
    edges.push_back({0, static_cast<uint64_t>(n - 1), truth[0] * truth[n - 1].inverse(), 1.0});
    const auto r = slam::optimisePoseGraph(poses, edges, {0}, 50);
    EXPECT_LT(r.finalCost, r.initialCost);
    EXPECT_TRUE(poses[0].isApprox(truth[0]));  // held still
    EXPECT_LT(err(n - 1), before / 10.0);
    double worst = 0.0;
    for (int k = 0; k < n; ++k)
        worst = std::max(worst, err(static_cast<uint64_t>(k)));
    EXPECT_LT(worst, before / 3.0);
    EXPECT_THROW(slam::optimisePoseGraph(poses, edges, {}, 5), std::invalid_argument);
}

TEST(PoseGraph, ConsistentEdgesGiveBackTheTruePoses)
{
    std::map<uint64_t, Eigen::Isometry3d> truth = {{0, pose(0.0, 0.0, {0, 0, 0})},
                                                   {1, pose(0.3, 0.1, {0.5, 0, 0.2})},
                                                   {2, pose(0.6, -0.1, {1.0, 0.1, 0.1})},
                                                   {3, pose(0.9, 0.0, {1.2, 0.3, 0.6})}};
    std::vector<slam::PoseGraphEdge> edges;
    for (uint64_t i = 0; i < 4; ++i)
        for (uint64_t j = i + 1; j < 4; ++j)
            edges.push_back({i, j, truth[i] * truth[j].inverse(), 1.0});
    auto poses = truth;
    for (uint64_t k = 1; k < 4; ++k)
        poses[k] = pose(0.05 * k, 0.02, {0.03, -0.02, 0.04}) * poses[k];
    slam::optimisePoseGraph(poses, edges, {0}, 50);
    for (uint64_t k = 0; k < 4; ++k)
    {
        EXPECT_LT((poses[k].translation() - truth[k].translation()).norm(), 1e-6) << k;
        EXPECT_LT(angleDeg(poses[k].inverse() * truth[k]), 1e-5) << k;
    }
}

TEST(LoopClosingParameters, InvalidValuesNameTheKey)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("loop_closing", "min_inliers", 2);
    slam::LoopClosingParameters p;
    try
    {
        p.loadFromConfigFile(cfg, "loop_closing");
        FAIL() << "min_inliers = 2 accepted";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("[loop_closing] min_inliers = 2"), std::string::npos)
            << e.what();
    }
    mrpt::config::CConfigFileMemory cfg2;
    cfg2.write("loop_closing", "neighbour_score_ratio", 1.5);
    EXPECT_THROW(p.loadFromConfigFile(cfg2, "loop_closing"), core::InputError);
}

namespace
{
Eigen::Isometry3d along(double x)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(-x, 0, 0);  // T_cam_world of a camera at (x, 0, 0)
    return T;
}
}  // namespace

// Six keyframes in a row, each sharing 150 points with the next, except that the last one was
// re-anchored: it shares none with the one before and sits 20 cm off, its own points with it. The
// loop to the first keyframe puts it back; the graph takes the correction on the step without
// shared points, the other keyframes keep their poses, the points move with their keyframe, and
// tracking is told.
TEST(LoopCorrection, StepWithoutSharedPointsTakesTheCorrectionAndPointsFollow)
{
    slam::Map map;
    const Eigen::Vector3d off(0.2, 0.0, 0.05);
    std::vector<std::shared_ptr<slam::KeyFrame>> kfs;
    for (int k = 0; k < 6; ++k)
    {
        Eigen::Isometry3d T = along(0.3 * k);
        if (k == 5)
            T = T * Eigen::Translation3d(-off);  // camera centre moved by +off
        kfs.push_back(map.createKeyFrame(test::frameWithKeypoints(300, T)));
    }
    std::vector<std::shared_ptr<slam::MapPoint>> lastPoints;
    for (int k = 0; k < 6; ++k)
    {
        for (size_t i = 0; i < 150; ++i)
        {
            const Eigen::Vector3d truth(0.3 * k + 0.01 * static_cast<double>(i), 0.5, 2.0);
            auto p = map.createPoint(k == 5 ? truth + off : truth, kfs[k].get());
            p->addObservation(kfs[k].get(), i);
            kfs[k]->points[i] = p;
            if (k < 4)  // seen by the next keyframe too (not across the re-anchoring)
            {
                p->addObservation(kfs[k + 1].get(), 150 + i);
                kfs[k + 1]->points[150 + i] = p;
            }
            if (k == 5)
                lastPoints.push_back(p);
        }
    }
    for (auto& kf : kfs)
        kf->updateConnections(15);
    slam::LoopMatch match;
    match.loop = kfs[0];
    match.T_cam_world = along(1.5);  // where keyframe 5 truly is
    std::vector<slam::PoseGraphEdge> loopEdges;
    const auto out = slam::correctLoop(map, kfs[5], match, loopEdges, 50, 15);
    EXPECT_EQ(out.keyframes, 6);
    ASSERT_EQ(loopEdges.size(), 1U);
    EXPECT_EQ(map.corrections(), 1U);
    EXPECT_LT((kfs[5]->centre_world() - Eigen::Vector3d(1.5, 0, 0)).norm(), 0.01);
    EXPECT_NEAR(out.moved_m, off.norm(), 0.01);
    for (int k = 0; k < 5; ++k)
        EXPECT_LT((kfs[k]->centre_world() - Eigen::Vector3d(0.3 * k, 0, 0)).norm(), 0.005) << k;
    for (size_t i = 0; i < lastPoints.size(); ++i)
        EXPECT_LT((lastPoints[i]->position_world -
                   Eigen::Vector3d(1.5 + 0.01 * static_cast<double>(i), 0.5, 2.0))
                      .norm(),
                  0.01)
            << i;
}
