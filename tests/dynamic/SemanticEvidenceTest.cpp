// Semantic evidence with known answers: a keyframe mask warped into a moved camera lands where
// the geometry says, only at the people's depth; labels follow a walking person along the
// Lucas-Kanade tracks and leave the background the person uncovers.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/dynamic/MovableLabelTracker.h"
#include "smap/dynamic/MovableMask.h"

using namespace smap;
using dynamic::MovableLabelTracker;
using dynamic::MovableMask;

namespace
{
core::PinholeCamera camera()
{
    return test::centredCamera(640, 480, 525.0);
}

/// Person (VOC 15) in a 64 x 160 px box at (288, 160), 2 m away; the rest background at 4 m.
struct Keyframe
{
    cv::Mat labels = cv::Mat(480, 640, CV_8UC1, cv::Scalar(0));
    cv::Mat depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(4.0F));
    std::vector<bool> movable = std::vector<bool>(21, false);
    Keyframe()
    {
        labels(cv::Rect(288, 160, 64, 160)).setTo(15);
        depth(cv::Rect(288, 160, 64, 160)).setTo(2.0F);
        movable[15] = true;
    }
};
}  // namespace

TEST(MovableMask, WarpsWithTheCameraAndOnlyAtThePeoplesDepth)
{
    const Keyframe k;
    const MovableMask mask(7, Eigen::Isometry3d::Identity(), k.labels, k.depth, camera(), k.movable,
                           4);
    EXPECT_EQ(mask.frameId(), 7U);
    EXPECT_EQ(mask.samples(), 16U * 40U);
    EXPECT_EQ(cv::countNonZero(mask.image()), 64 * 160);

    // Same pose, no growth: the box's cells and nothing else.
    const auto same = mask.project(Eigen::Isometry3d::Identity(), camera(), 0.0);
    EXPECT_TRUE(same.contains(320.0F, 240.0F, 2.0F, 0.5F));
    EXPECT_FALSE(same.contains(250.0F, 240.0F, 2.0F, 0.5F));
    EXPECT_FALSE(same.contains(320.0F, 240.0F, 4.0F, 0.5F)) << "the wall behind is not a person";
    EXPECT_TRUE(same.contains(320.0F, 240.0F, 0.0F, 0.5F)) << "no depth: the mask decides";

    // The camera moves 0.2 m to the right: a point 2 m away moves 52.5 px to the left.
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.translation() = Eigen::Vector3d(0.2, 0.0, 0.0);
    const auto moved = mask.project(T_world_cam, camera(), 0.0);
    EXPECT_TRUE(moved.contains(240.0F, 240.0F, 2.0F, 0.5F));
    EXPECT_FALSE(moved.contains(345.0F, 240.0F, 2.0F, 0.5F));
    // Grown by 24 px: the cells beside the box join.
    const auto grown = mask.project(T_world_cam, camera(), 24.0);
    EXPECT_TRUE(grown.contains(305.0F, 240.0F, 2.0F, 0.5F));
    EXPECT_GT(grown.coverage(), moved.coverage());
}

TEST(MovableMask, EmptyWithoutMovablePixels)
{
    Keyframe k;
    k.movable[15] = false;
    const MovableMask mask(0, Eigen::Isometry3d::Identity(), k.labels, k.depth, camera(), k.movable,
                           4);
    EXPECT_TRUE(mask.empty());
    EXPECT_TRUE(mask.project(Eigen::Isometry3d::Identity(), camera(), 10.0).empty());
}

namespace
{
/// Frame `id` of a person walking 6 px per frame to the right, 2 m away, in front of a wall
/// 4 m away: keypoints on a 10 px grid, tracks 2 frames back (the strong filter's gap).
MovableLabelTracker::FrameTracks walkingFrame(uint64_t id)
{
    MovableLabelTracker::FrameTracks t;
    t.frameId = id;
    t.framesBack = id >= 2 ? 2 : 0;
    const float x0 = 200.0F + 6.0F * static_cast<float>(id);
    for (float v = 105.0F; v < 400.0F; v += 10.0F)
    {
        for (float u = 5.0F; u < 640.0F; u += 10.0F)
        {
            const bool person = u >= x0 && u < x0 + 60.0F && v >= 150.0F && v < 350.0F;
            t.keypoints.emplace_back(u, v);
            t.depth.push_back(person ? 2.0F : 4.0F);
            // A person's point was 12 px to the left two frames earlier; the wall's stays put.
            t.inReference.emplace_back(person ? u - 12.0F : u, v);
        }
    }
    return t;
}

bool onPerson(const MovableLabelTracker::FrameTracks& t, size_t i)
{
    return t.depth[i] < 3.0F;
}
}  // namespace

TEST(MovableLabelTracker, LabelsFollowAWalkingPersonAndLeaveTheWall)
{
    MovableLabelTracker tracker(40, 0.5);
    for (uint64_t id = 0; id < 12; ++id)
    {
        const auto& labels = tracker.add(walkingFrame(id));
        for (const auto l : labels)
            EXPECT_EQ(l, MovableLabelTracker::Label::Unknown) << "no mask yet";
    }
    // The mask of frame 5 arrives (the person's box at frame 5), then frame 12.
    cv::Mat image(480, 640, CV_8UC1, cv::Scalar(0));
    image(cv::Rect(230, 150, 60, 200)).setTo(255);
    tracker.setMask(5, image);
    const auto t = walkingFrame(12);
    const auto labels = tracker.add(t);
    size_t personMovable = 0, person = 0, wallMovable = 0;
    for (size_t i = 0; i < labels.size(); ++i)
    {
        if (onPerson(t, i))
        {
            person++;
            personMovable += labels[i] == MovableLabelTracker::Label::Movable ? 1 : 0;
        }
        else
        {
            wallMovable += labels[i] == MovableLabelTracker::Label::Movable ? 1 : 0;
        }
    }
    // 42 px from where the mask saw it: the mask itself (the camera did not move) covers 18 of
    // the person's 60 px now, 30 %; along the tracks at least three quarters stay labelled
    // (the strict majority loses some of the edge columns).
    EXPECT_GE(personMovable, person * 3 / 4);
    EXPECT_EQ(wallMovable, 0U) << "uncovered wall is farther than the person: static";
}
