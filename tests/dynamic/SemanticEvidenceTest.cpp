// Semantic evidence with known answers: a keyframe mask warped into a moved camera lands where
// the geometry says, only at the people's depth; labels follow a walking person along the
// Lucas-Kanade tracks and leave the background the person uncovers; a still keypoint on a
// clearly still person is movable even when its track carried a static label.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/dynamic/MovableLabelTracker.h"
#include "smap/dynamic/MovableMask.h"
#include "smap/dynamic/MovableVerdict.h"

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
/// Frame `id` of a person walking `speed` px per frame to the right (0: standing), 2 m away, in
/// front of a wall `wallDepth` m away: keypoints on a 10 px grid, tracks 2 frames back (the
/// strong filter's gap). With `flow`, the flow test's verdict too: the walker moving, the rest
/// still.
MovableLabelTracker::FrameTracks walkingFrame(uint64_t id, float speed = 6.0F,
                                              float wallDepth = 4.0F, bool flow = false)
{
    MovableLabelTracker::FrameTracks t;
    t.frameId = id;
    t.timestamp = static_cast<double>(id) / 30.0;
    t.framesBack = id >= 2 ? 2 : 0;
    const float x0 = 200.0F + speed * static_cast<float>(id);
    for (float v = 105.0F; v < 400.0F; v += 10.0F)
    {
        for (float u = 5.0F; u < 640.0F; u += 10.0F)
        {
            const bool person = u >= x0 && u < x0 + 60.0F && v >= 150.0F && v < 350.0F;
            t.keypoints.emplace_back(u, v);
            t.depth.push_back(person ? 2.0F : wallDepth);
            // A person's point was 2 x speed px to the left two frames earlier; the wall's
            // stays put.
            t.inReference.emplace_back(person ? u - 2.0F * speed : u, v);
            if (flow)
                t.motion.push_back(person && speed > 0.0F ? MovableLabelTracker::Motion::Moving
                                                          : MovableLabelTracker::Motion::Still);
        }
    }
    return t;
}

bool onPerson(const MovableLabelTracker::FrameTracks& t, size_t i)
{
    return t.depth[i] < 2.1F;
}

struct LabelTally
{
    size_t person = 0, personMovable = 0, wallMovable = 0;
};

/// Frames 0-11 join the tracker, the mask of frame 5 arrives (the person's box there), then
/// frame 12: how its labels fall.
LabelTally labelsAfterAMask(float speed, float wallDepth, bool flow)
{
    MovableLabelTracker tracker(40.0 / 30.0, 0.5);  // 40 frames
    for (uint64_t id = 0; id < 12; ++id)
        tracker.add(walkingFrame(id, speed, wallDepth, flow));
    cv::Mat image(480, 640, CV_8UC1, cv::Scalar(0));
    image(cv::Rect(static_cast<int>(200.0F + 5.0F * speed), 150, 60, 200)).setTo(255);
    tracker.setMask(5, image);
    const auto t = walkingFrame(12, speed, wallDepth, flow);
    const auto labels = tracker.add(t);
    LabelTally n;
    for (size_t i = 0; i < labels.size(); ++i)
    {
        const bool movable = labels[i] == MovableLabelTracker::Label::Movable;
        if (onPerson(t, i))
        {
            n.person++;
            n.personMovable += movable ? 1 : 0;
        }
        else
        {
            n.wallMovable += movable ? 1 : 0;
        }
    }
    return n;
}
}  // namespace

TEST(MovableLabelTracker, LabelsFollowAWalkingPersonAndLeaveTheWall)
{
    MovableLabelTracker tracker(40.0 / 30.0, 0.5);  // 40 frames
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

TEST(MovableLabelTracker, BackgroundAWalkerUncoversAtTheirDepthStaysStatic)
{
    // The wall 0.3 m behind the walker: the depth test cannot tell the uncovered wall from the
    // person. Without the flow test's verdicts the label spreads onto the wall behind them.
    const LabelTally blind = labelsAfterAMask(6.0F, 2.3F, false);
    EXPECT_GT(blind.wallMovable, 10U);
    // With them, a still keypoint counts only the still keypoints around its track: the wall.
    const LabelTally n = labelsAfterAMask(6.0F, 2.3F, true);
    EXPECT_EQ(n.wallMovable, 0U);
    EXPECT_GE(n.personMovable, n.person * 3 / 4);
}

TEST(MovableLabelTracker, APersonStandingStillKeepsTheLabel)
{
    // Still like the wall: the still keypoints around the tracks are the person's own, so the
    // flow test's verdicts change nothing (the strict majority loses an edge column or two).
    const LabelTally n = labelsAfterAMask(0.0F, 2.3F, true);
    const LabelTally blind = labelsAfterAMask(0.0F, 2.3F, false);
    EXPECT_EQ(n.personMovable, blind.personMovable);
    EXPECT_GE(n.personMovable, n.person * 3 / 4);
    EXPECT_EQ(n.wallMovable, 0U);
}

namespace
{
/// Frame 3 of `tracker`: keypoints on a 10 px grid over x 105-455, y 205-295, 2 m away, the flow
/// test's verdict `moving(u, v)`; returns the mask of two people, at x 100-159 and x 400-459.
template <typename Moving>
cv::Mat twoPeopleOnFrame3(MovableLabelTracker& tracker, Moving moving)
{
    MovableLabelTracker::FrameTracks t;
    t.frameId = 3;
    t.timestamp = 0.1;
    for (float u = 105.0F; u < 460.0F; u += 10.0F)
    {
        for (float v = 205.0F; v < 300.0F; v += 10.0F)
        {
            t.keypoints.emplace_back(u, v);
            t.depth.push_back(2.0F);
            t.inReference.emplace_back(u, v);
            t.motion.push_back(moving(u, v) ? MovableLabelTracker::Motion::Moving
                                            : MovableLabelTracker::Motion::Still);
        }
    }
    tracker.add(t);
    cv::Mat image(480, 640, CV_8UC1, cv::Scalar(0));
    image(cv::Rect(100, 200, 60, 100)).setTo(255);
    image(cv::Rect(400, 200, 60, 100)).setTo(255);
    return image;
}
}  // namespace

TEST(MovableLabelTracker, MovingPartsAreTheMaskRegionsTheFlowSawMoving)
{
    MovableLabelTracker tracker(10.0 / 30.0, 0.5);  // 10 frames
    // A walker at x 100-159 (moving keypoints) and a seated person at x 400-459.
    const cv::Mat image =
        twoPeopleOnFrame3(tracker, [](float u, float /*v*/) { return u < 200.0F; });
    const cv::Mat moving = tracker.movingParts(3, image, 2.0 / 3.0);
    EXPECT_EQ(cv::countNonZero(moving(cv::Rect(100, 200, 60, 100))), 60 * 100);
    EXPECT_EQ(cv::countNonZero(moving), 60 * 100) << "the seated person and the rest stay";
    EXPECT_EQ(cv::countNonZero(tracker.movingParts(4, image, 2.0 / 3.0)), 0)
        << "frame 4 is not kept";
}

TEST(MovableMask, WithoutLeavesOutTheDroppedPixels)
{
    const Keyframe k;
    const MovableMask mask(0, Eigen::Isometry3d::Identity(), k.labels, k.depth, camera(), k.movable,
                           4);
    cv::Mat drop(480, 640, CV_8UC1, cv::Scalar(0));
    drop(cv::Rect(288, 160, 32, 160)).setTo(255);  // the person's left half
    const MovableMask half = mask.without(drop);
    EXPECT_EQ(half.frameId(), mask.frameId());
    EXPECT_EQ(half.samples(), mask.samples() / 2);
    EXPECT_EQ(cv::countNonZero(half.image()), 32 * 160);
    const auto cells = half.project(Eigen::Isometry3d::Identity(), camera(), 0.0);
    EXPECT_FALSE(cells.contains(292.0F, 240.0F, 2.0F, 0.5F));
    EXPECT_TRUE(cells.contains(340.0F, 240.0F, 2.0F, 0.5F));
    drop.setTo(255);
    EXPECT_TRUE(mask.without(drop).empty());
}

TEST(MovableLabelTracker, ALowerFractionTakesInASwayingPerson)
{
    // A person at x 100-159 of whom half the measured keypoints moved (swaying), one at
    // x 400-459 who stood still.
    MovableLabelTracker tracker(10.0 / 30.0, 0.5);  // 10 frames
    const cv::Mat image = twoPeopleOnFrame3(
        tracker, [](float u, float v) { return u < 200.0F && static_cast<int>(v) % 20 == 5; });
    EXPECT_EQ(cv::countNonZero(tracker.movingParts(3, image, 2.0 / 3.0)), 0)
        << "half moving is no walker";
    const cv::Mat moving = tracker.movingParts(3, image, 0.34);
    EXPECT_EQ(cv::countNonZero(moving(cv::Rect(100, 200, 60, 100))), 60 * 100);
    EXPECT_EQ(cv::countNonZero(moving), 60 * 100) << "the still person stays clearly still";
}

namespace
{
/// Cells (8 px) marked over `box` (pixels), their nearest sample depth `z`.
dynamic::MovableCells cellsOver(const cv::Rect& box, float z)
{
    dynamic::MovableCells c;
    c.cells = cv::Mat(60, 80, CV_8UC1, cv::Scalar(0));
    c.nearest = cv::Mat(60, 80, CV_32FC1, cv::Scalar(0.0F));
    const cv::Rect inCells(box.x / 8, box.y / 8, box.width / 8, box.height / 8);
    c.cells(inCells).setTo(1);
    c.nearest(inCells).setTo(z);
    return c;
}
}  // namespace

TEST(MovableVerdict, AStillKeypointOnAClearlyStillPersonIsMovableWhateverItsLabel)
{
    using Label = MovableLabelTracker::Label;
    using Motion = MovableLabelTracker::Motion;
    dynamic::MovableEvidence e;
    // The still person at x 320-383, 2 m away; the grown mask 40 px wider each side.
    e.still = cellsOver(cv::Rect(320, 160, 64, 160), 2.0F);
    e.grown = cellsOver(cv::Rect(280, 120, 144, 240), 2.0F);
    struct Case
    {
        cv::Point2f at;
        float z;
        Label label;
        Motion motion;
        bool movable;
        const char* why;
    };
    const std::vector<Case> cases = {
        {{340, 200}, 2.0F, Label::Static, Motion::Still, true, "on the still person"},
        {{340, 200}, 2.0F, Label::Static, Motion::Moving, false, "moving: its label decides"},
        {{340, 200}, 2.0F, Label::Static, Motion::Untracked, false, "unmeasured: its label"},
        {{300, 200}, 2.0F, Label::Static, Motion::Still, false, "only in the grown mask"},
        {{340, 200}, 3.0F, Label::Static, Motion::Still, false, "behind the person"},
        {{300, 200}, 2.0F, Label::Unknown, Motion::Still, true, "no label: the grown mask"},
        {{100, 200}, 2.0F, Label::Unknown, Motion::Still, false, "no label, outside"},
        {{100, 200}, 2.0F, Label::Movable, Motion::Moving, true, "labelled along its track"},
    };
    for (const Case& c : cases)
    {
        e.pixels.push_back(c.at);
        e.depth.push_back(c.z);
        e.labels.push_back(c.label);
        e.motion.push_back(c.motion);
    }
    const std::vector<bool> movable = dynamic::movableVerdicts(e);
    ASSERT_EQ(movable.size(), cases.size());
    for (size_t i = 0; i < cases.size(); ++i)
        EXPECT_EQ(movable[i], cases[i].movable) << cases[i].why;
    // Without the clearly still mask (still_dilation_px < 0) the label decides.
    e.still = {};
    EXPECT_FALSE(dynamic::movableVerdicts(e)[0]);
}
