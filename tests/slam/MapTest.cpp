// Map bookkeeping with known answers: observations, covisibility, point fusion and keyframe
// culling that keeps a culled keyframe's pose tied to its parent.
#include <gtest/gtest.h>

#include "KeyFrameFixtures.h"
#include "smap/slam/Map.h"

using namespace smap;

TEST(Map, CovisibilityCountsSharedPointsAndCullingFollowsTheParent)
{
    slam::Map map;
    Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T2 = T1;
    T2.translation() = Eigen::Vector3d(0.1, 0, 0);
    auto a = map.createKeyFrame(test::frameWithKeypoints(30, T1));
    auto b = map.createKeyFrame(test::frameWithKeypoints(30, T2));
    // 20 points seen by both, 10 only by a.
    for (size_t i = 0; i < 30; ++i)
    {
        auto p = map.createPoint(Eigen::Vector3d(0.01 * static_cast<double>(i), 0, 2), a.get());
        p->addObservation(a.get(), i);
        a->points[i] = p;
        if (i < 20)
        {
            p->addObservation(b.get(), i);
            b->points[i] = p;
        }
    }
    a->updateConnections(15);
    EXPECT_EQ(a->weight(b.get()), 20);
    EXPECT_EQ(b->weight(a.get()), 20);
    EXPECT_EQ(a->bestCovisibles(), std::vector<slam::KeyFrame*>{b.get()});
    EXPECT_EQ(b->trackedPoints(2), 20);

    // Fusing: point 25 (seen by a only) replaced by point 0 moves a's observation.
    auto p0 = a->points[0];
    auto p25 = a->points[25];
    p25->replaceWith(p0);
    EXPECT_TRUE(p25->isBad());
    EXPECT_EQ(p25->replacement(), p0);
    EXPECT_FALSE(a->points[25]) << "a already observes p0 at keypoint 0";

    // Culling a with parent b: observations go, b's pose changes later, a follows rigidly.
    const Eigen::Isometry3d T_a_b = a->T_cam_world() * b->T_cam_world().inverse();
    a->setBad(b);
    EXPECT_TRUE(a->isBad());
    EXPECT_EQ(b->weight(a.get()), 0);
    EXPECT_EQ(p0->numObservations(), 0U);
    EXPECT_TRUE(p0->isBad()) << "a point left with one observation is bad";
    Eigen::Isometry3d T2moved = T2;
    T2moved.translation() += Eigen::Vector3d(0, 0.5, 0);
    b->setPose(T2moved);
    EXPECT_TRUE(a->resolvedT_cam_world().isApprox(T_a_b * T2moved, 1e-12));
    map.removeBad();
    EXPECT_EQ(map.keyframes().size(), 1U);
    EXPECT_EQ(map.allKeyFrames().size(), 2U);
    EXPECT_EQ(map.points().size(), 0U) << "every point lost its second observation";
}

// The tracker numbers its local-map searches from 1 and takes a point seen by several local
// keyframes once per search.
TEST(Map, APointIsMarkedOncePerLocalMapSearch)
{
    slam::MapPoint point(7, Eigen::Vector3d(0.0, 0.0, 1.0), nullptr);
    EXPECT_TRUE(point.markForSearch(1));
    EXPECT_FALSE(point.markForSearch(1));
    EXPECT_TRUE(point.markForSearch(2));
    EXPECT_FALSE(point.markForSearch(2));
}
