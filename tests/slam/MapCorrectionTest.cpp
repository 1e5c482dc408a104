// A correction computed on a snapshot of the map reaches what was created meanwhile: a keyframe
// absent from the snapshot follows its newest keyframe, and every point keeps its place in the
// frame of the camera that first observed it.
#include <gtest/gtest.h>

#include "KeyFrameFixtures.h"
#include "smap/slam/Map.h"
#include "smap/slam/MapCorrection.h"

using namespace smap;

namespace
{
Eigen::Isometry3d pose(double yaw, const Eigen::Vector3d& t)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() =
        Eigen::AngleAxisd(yaw, Eigen::Vector3d(0.1, 1.0, 0.2).normalized()).toRotationMatrix();
    T.translation() = t;
    return T;
}

std::shared_ptr<slam::MapPoint> pointSeenBy(slam::Map& map, slam::KeyFrame& kf, size_t index,
                                            const Eigen::Vector3d& p_world)
{
    auto mp = map.createPoint(p_world, &kf);
    mp->addObservation(&kf, index);
    kf.points[index] = mp;
    return mp;
}
}  // namespace

TEST(MapCorrection, WhatTheSnapshotDidNotHoldFollowsItsNewestKeyFrame)
{
    slam::Map map;
    std::vector<std::shared_ptr<slam::KeyFrame>> kfs;
    kfs.reserve(4);
    for (int k = 0; k < 4; ++k)
        kfs.push_back(map.createKeyFrame(
            test::frameWithKeypoints(3, pose(0.1 * k, Eigen::Vector3d(0.3 * k, 0.0, 0.05 * k)))));
    const auto seenFirstBy1 = pointSeenBy(map, *kfs[1], 0, {0.4, 0.1, 2.0});
    const auto seenFirstBy3 = pointSeenBy(map, *kfs[3], 0, {1.1, -0.2, 2.5});
    const auto placed = pointSeenBy(map, *kfs[2], 0, {0.7, 0.0, 2.2});
    std::vector<Eigen::Isometry3d> before;
    before.reserve(kfs.size());
    for (const auto& kf : kfs)
        before.push_back(kf->T_cam_world());
    const Eigen::Vector3d placedBefore = placed->position_world;
    const Eigen::Vector3d in1 = kfs[1]->T_cam_world() * seenFirstBy1->position_world;
    const Eigen::Vector3d in3 = kfs[3]->T_cam_world() * seenFirstBy3->position_world;

    // The snapshot held keyframes 0-2; keyframe 3 was created while it was corrected.
    std::map<uint64_t, Eigen::Isometry3d> old, corrected;
    for (int k = 0; k < 3; ++k)
        old[kfs[static_cast<size_t>(k)]->id()] = before[static_cast<size_t>(k)];
    corrected = old;
    corrected[kfs[1]->id()] = pose(0.15, {0.25, 0.02, 0.1});
    corrected[kfs[2]->id()] = pose(0.3, {0.5, 0.05, 0.2});
    slam::applyCorrections(map, slam::correctionsBetween(old, corrected), {placed->id()});

    EXPECT_TRUE(kfs[0]->T_cam_world().isApprox(before[0], 1e-12));
    EXPECT_TRUE(kfs[1]->T_cam_world().isApprox(corrected[kfs[1]->id()], 1e-12));
    EXPECT_TRUE(kfs[2]->T_cam_world().isApprox(corrected[kfs[2]->id()], 1e-12));
    // Keyframe 3 keeps its pose relative to keyframe 2, the newest of the snapshot.
    const Eigen::Isometry3d T_3_2_before = before[3] * before[2].inverse();
    const Eigen::Isometry3d T_3_2_after = kfs[3]->T_cam_world() * kfs[2]->T_cam_world().inverse();
    EXPECT_TRUE(T_3_2_after.isApprox(T_3_2_before, 1e-9));
    EXPECT_FALSE(kfs[3]->T_cam_world().isApprox(before[3], 1e-3)) << "keyframe 3 moved";
    // Points stay where their first observer saw them; a point already placed is left alone.
    EXPECT_TRUE((kfs[1]->T_cam_world() * seenFirstBy1->position_world).isApprox(in1, 1e-9));
    EXPECT_TRUE((kfs[3]->T_cam_world() * seenFirstBy3->position_world).isApprox(in3, 1e-9));
    EXPECT_TRUE(placed->position_world.isApprox(placedBefore, 1e-12));
}

TEST(MapCorrection, CorrectionsAreOnlyForKeyFramesOfTheSnapshot)
{
    const std::map<uint64_t, Eigen::Isometry3d> old = {{0, pose(0.0, {0, 0, 0})},
                                                       {1, pose(0.2, {1, 0, 0})}};
    const std::map<uint64_t, Eigen::Isometry3d> corrected = {{1, pose(0.3, {1, 0.1, 0})},
                                                             {2, pose(0.5, {2, 0, 0})}};
    const auto C = slam::correctionsBetween(old, corrected);
    ASSERT_EQ(C.size(), 1U);
    EXPECT_TRUE((old.at(1) * C.at(1)).isApprox(corrected.at(1), 1e-12));
}
