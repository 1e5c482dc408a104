// SemanticMapBuilder: contributions in the camera frame, thinning, and re-anchoring at refined
// poses against known geometry.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/mapping/SemanticMapBuilder.h"

using namespace smap;

namespace
{
core::PinholeCamera camera()
{
    return test::centredCamera(80, 60, 80.0);
}

/// A wall 2 m in front, label 9 (chair) on the left half, 15 (person, dynamic) on a square.
maps::BackProjector::Images wall()
{
    maps::BackProjector::Images im;
    im.colour = cv::Mat(60, 80, CV_8UC3, cv::Scalar(30, 60, 90));
    im.depth = cv::Mat(60, 80, CV_32FC1, cv::Scalar(2.0f));
    im.labels = cv::Mat(60, 80, CV_8UC1, cv::Scalar(0));
    im.labels(cv::Rect(0, 0, 40, 60)).setTo(9);
    im.confidence = cv::Mat(60, 80, CV_32FC1, cv::Scalar(0.9f));
    im.dynamicMask = cv::Mat(60, 80, CV_8UC1, cv::Scalar(0));
    im.dynamicMask(cv::Rect(50, 20, 10, 10)).setTo(255);
    im.labels(cv::Rect(50, 20, 10, 10)).setTo(15);
    return im;
}

/// The wall with no dynamic pixels (a keyframe that sees no mover).
maps::BackProjector::Images bareWall()
{
    maps::BackProjector::Images im = wall();
    im.dynamicMask.setTo(0);
    return im;
}

/// A copy of im whose depth is z on r (its own depth image: cv::Mat copies share pixels).
maps::BackProjector::Images withDepth(const maps::BackProjector::Images& im, const cv::Rect& r,
                                      float z)
{
    maps::BackProjector::Images out = im;
    out.depth = im.depth.clone();
    out.depth(r).setTo(z);
    return out;
}

double meanZ(const maps::CSemanticPointsMap& m)
{
    double z = 0.0;
    const auto pts = m.points();
    for (const auto& p : pts)
        z += p.position.z();
    return z / static_cast<double>(pts.size());
}

/// The wall with patch A 1 m in front (x -0.09 .. 0 m), right beside pixels the dynamic mask
/// caught (a person), and patch B 1 m in front (x -0.5 .. -0.39 m), 0.4 m away from them.
maps::BackProjector::Images patchesBesideAMover()
{
    maps::BackProjector::Images im = wall();
    im.dynamicMask.setTo(0);
    im.depth(cv::Rect(32, 15, 8, 20)).setTo(1.0f);  // A
    im.depth(cv::Rect(40, 15, 6, 20)).setTo(1.0f);  // the mover beside it
    im.dynamicMask(cv::Rect(40, 15, 6, 20)).setTo(255);
    im.depth(cv::Rect(0, 45, 10, 10)).setTo(1.0f);  // B
    return im;
}

/// patchesBesideAMover seen again with the mover gone: no depth and no dynamic pixels where it
/// was, A where it was.
maps::BackProjector::Images patchesWithoutTheMover()
{
    maps::BackProjector::Images im =
        withDepth(patchesBesideAMover(), cv::Rect(40, 15, 6, 20), 0.0f);
    im.dynamicMask.setTo(0);
    return im;
}

/// The near-mover tests within 0.1 m of a keyframe's dynamic pixels, the clear test off: two
/// keyframes confirm what they both saw beside a mover.
mapping::MapBuilderParameters nearMoversWithoutClearTest()
{
    mapping::MapBuilderParameters p;
    p.prune_near_movers = 0.1;
    p.confirm_clear_distance = 0.0;
    return p;
}

/// Points of m in front of the wall with x in [xMin, xMax).
size_t pointsInFront(const maps::CSemanticPointsMap& m, float xMin, float xMax)
{
    size_t n = 0;
    for (const auto& q : m.points())
        n += q.position.z() < 1.5f && q.position.x() >= xMin && q.position.x() < xMax ? 1 : 0;
    return n;
}
/// Points of m in front of the wall with z in [zMin, 1.5).
size_t pointsBehind(const maps::CSemanticPointsMap& m, float zMin)
{
    size_t n = 0;
    for (const auto& q : m.points())
        n += q.position.z() >= zMin && q.position.z() < 1.5f ? 1 : 0;
    return n;
}

/// Points of m on patch A, on patch B (patchesBesideAMover) and elsewhere (the wall).
struct PatchCounts
{
    size_t a = 0, b = 0, wall = 0;
};
PatchCounts countPatches(const maps::CSemanticPointsMap& m)
{
    PatchCounts n;
    n.a = pointsInFront(m, -0.2f, 0.05f);
    n.b = pointsInFront(m, -1.0f, -0.35f);
    n.wall = m.size() - n.a - n.b;
    return n;
}
}  // namespace

TEST(SemanticMapBuilder, ContributionIsTheStaticPixelsInTheCameraFrameThinned)
{
    mapping::MapBuilderParameters p;
    p.contribution_voxel = 0.0;
    mapping::SemanticMapBuilder full(p, core::LabelSet::pascalVoc());
    const mrpt::poses::CPose3D T(1.0, 2.0, 3.0, 0.0, 0.0, 0.0);
    const auto& c = full.add(0, 0, 10.0, wall(), camera(), T);
    // 80 x 60 pixels minus the 10 x 10 dynamic square.
    EXPECT_EQ(c.points_cam.size(), 80u * 60u - 100u);
    for (const auto& pt : c.points_cam)
    {
        EXPECT_NEAR(pt.position.z(), 2.0f, 1e-5f);
        EXPECT_NE(pt.label, 15) << "dynamic pixels never reach the map";
    }
    // In the world, the wall is at z = 3 + 2.
    EXPECT_NEAR(meanZ(full.pointsMap()), 5.0, 1e-4);
    EXPECT_FALSE(full.octoMap().isEmpty());

    // Thinned to 2 cm voxels: at 2 m a pixel is 2.5 cm, so about one point per pixel remains,
    // and at 10 cm a 4 x 4-pixel block becomes one point.
    p.contribution_voxel = 0.1;
    mapping::SemanticMapBuilder thin(p, core::LabelSet::pascalVoc());
    const auto& t = thin.add(0, 0, 10.0, wall(), camera(), T);
    EXPECT_LT(t.points_cam.size(), c.points_cam.size() / 8);
    EXPECT_GT(t.points_cam.size(), c.points_cam.size() / 32);
    EXPECT_GT(thin.contributionBytes(), t.points_cam.size() * sizeof(maps::SemanticPoint));
}

TEST(SemanticMapBuilder, ReanchorMovesTheMapOnlyBeyondTheTolerance)
{
    mapping::MapBuilderParameters p;
    // The wall's person square: no test near movers here (two walls 0.5 m apart would be
    // one seen through the other).
    p.confirm_near_movers = 0;
    p.see_through_margin = 0.0;
    mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
    const mrpt::poses::CPose3D T0(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    b.add(0, 0, 1.0, wall(), camera(), T0);
    b.add(1, 1, 2.0, wall(), camera(), T0);
    const size_t before = b.pointsMap().size();
    EXPECT_NEAR(meanZ(b.pointsMap()), 2.0, 1e-3);

    // 5 mm: within the 1 cm tolerance, nothing is rebuilt.
    auto small = b.reanchor([](const mapping::KeyFrameContribution&)
                            { return mrpt::poses::CPose3D(0.0, 0.0, 0.005, 0.0, 0.0, 0.0); });
    EXPECT_EQ(small.moved, 0u);
    EXPECT_FALSE(small.rebuilt);
    EXPECT_NEAR(small.maxTranslation, 0.005, 1e-9);
    EXPECT_NEAR(meanZ(b.pointsMap()), 2.0, 1e-3);

    // Keyframe 1 refined 0.5 m further along z: rebuilt, half the wall moves with it.
    auto big = b.reanchor(
        [](const mapping::KeyFrameContribution& c) -> std::optional<mrpt::poses::CPose3D>
        {
            if (c.keyframe == 1)
                return mrpt::poses::CPose3D(0.0, 0.0, 0.5, 0.0, 0.0, 0.0);
            return std::nullopt;
        });
    EXPECT_EQ(big.moved, 1u);
    EXPECT_TRUE(big.rebuilt);
    EXPECT_NEAR(big.maxTranslation, 0.5, 1e-9);
    EXPECT_EQ(b.pointsMap().size(), 2 * before) << "two walls now, 0.5 m apart";
    EXPECT_NEAR(meanZ(b.pointsMap()), 2.25, 1e-3);
    EXPECT_EQ(b.contributions()[1].T_world_cam.z(), 0.5);

    // A 5 degree rotation is beyond the 1 degree tolerance.
    auto turned = b.reanchor(
        [](const mapping::KeyFrameContribution& c) {
            return mrpt::poses::CPose3D(0.0, 0.0, c.T_world_cam.z(), 5.0 * M_PI / 180.0, 0.0, 0.0);
        });
    EXPECT_EQ(turned.moved, 2u);
    EXPECT_NEAR(turned.maxRotationDeg, 5.0, 1e-6);
}

// Keyframes of a part of the SLAM map that was dropped leave the maps: the rebuild holds the
// rest only.
TEST(SemanticMapBuilder, ReanchorDropsDiscardedKeyFrames)
{
    mapping::MapBuilderParameters p;
    p.confirm_near_movers = 0;
    p.see_through_margin = 0.0;
    mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
    const mrpt::poses::CPose3D T0(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    const mrpt::poses::CPose3D T1(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
    b.add(0, 0, 1.0, wall(), camera(), T0);
    const size_t one = b.pointsMap().size();
    b.add(1, 1, 2.0, wall(), camera(), T1);
    ASSERT_EQ(b.pointsMap().size(), 2 * one);
    const auto r = b.reanchor(
        [](const mapping::KeyFrameContribution&) { return std::optional<mrpt::poses::CPose3D>(); },
        [](const mapping::KeyFrameContribution& c) { return c.frameId == 1; });
    EXPECT_EQ(r.discarded, 1U);
    EXPECT_EQ(r.moved, 0U);
    EXPECT_TRUE(r.rebuilt);
    ASSERT_EQ(b.contributions().size(), 1U);
    EXPECT_EQ(b.contributions()[0].frameId, 0U);
    EXPECT_EQ(b.pointsMap().size(), one);
    EXPECT_NEAR(meanZ(b.pointsMap()), 2.0, 1e-3) << "the wall seen from z = 0 only";
}

TEST(SemanticMapBuilder, PruningDropsPointsWhereLaterKeyframesSawThrough)
{
    // Keyframe 0 sees a box 1 m in front of the wall that the dynamic mask missed (a person who
    // then left); keyframes 1-3 see the bare wall through where it stood. The octomap carves
    // the box's voxels free; with pruning the points map drops the box's points as well.
    maps::BackProjector::Images withBox = wall();
    withBox.dynamicMask.setTo(0);
    withBox.depth(cv::Rect(20, 15, 20, 20)).setTo(1.0f);
    const maps::BackProjector::Images bare = bareWall();
    const auto nearPoints = [](const maps::CSemanticPointsMap& m)
    {
        size_t n = 0;
        for (const auto& p : m.points())
            n += p.position.z() < 1.5f ? 1 : 0;
        return n;
    };
    for (const bool prune : {false, true})
    {
        mapping::MapBuilderParameters p;
        p.prune_free_points = prune;
        mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
        b.add(0, 0, 0.0, withBox, camera(), mrpt::poses::CPose3D());
        for (uint64_t k = 1; k <= 3; ++k)
            b.add(k, k, static_cast<double>(k), bare, camera(), mrpt::poses::CPose3D());
        const size_t boxBefore = nearPoints(b.pointsMap());
        const size_t wallBefore = b.pointsMap().size() - boxBefore;
        ASSERT_GT(boxBefore, 50U);
        const size_t pruned = b.pruneFreePoints();
        EXPECT_EQ(nearPoints(b.pointsMap()), prune ? 0U : boxBefore) << "prune " << prune;
        EXPECT_EQ(pruned, prune ? boxBefore : 0U);
        EXPECT_EQ(b.pointsMap().size() - nearPoints(b.pointsMap()), wallBefore);
    }
}

TEST(SemanticMapBuilder, PruningNearMoversDropsOnlyWhatStoodBesideAMover)
{
    // Keyframe 0: box A 1 m in front, right beside pixels the dynamic mask caught (a person),
    // and box B 1 m in front, 0.4 m away from them; keyframes 1-3 see the bare wall through
    // both. Only A is beside a mover: only A goes; B and the wall stay.
    const maps::BackProjector::Images first = patchesBesideAMover();
    const maps::BackProjector::Images bare = bareWall();
    const auto count = pointsInFront;
    mapping::MapBuilderParameters p;
    p.prune_near_movers = 0.1;
    mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
    b.add(0, 0, 0.0, first, camera(), mrpt::poses::CPose3D());
    for (uint64_t k = 1; k <= 3; ++k)
        b.add(k, k, static_cast<double>(k), bare, camera(), mrpt::poses::CPose3D());
    const size_t a = count(b.pointsMap(), -0.2f, 0.05f), boxB = count(b.pointsMap(), -1.0f, -0.35f);
    const size_t wallBefore = b.pointsMap().size() - a - boxB;
    ASSERT_GT(a, 20U);
    ASSERT_GT(boxB, 20U);
    EXPECT_EQ(b.pruneFreePoints(), a);
    EXPECT_EQ(count(b.pointsMap(), -0.2f, 0.05f), 0U);
    EXPECT_EQ(count(b.pointsMap(), -1.0f, -0.35f), boxB);
    EXPECT_EQ(b.pointsMap().size() - boxB, wallBefore);
    // Off: nothing goes.
    p.prune_near_movers = 0.0;
    mapping::SemanticMapBuilder off(p, core::LabelSet::pascalVoc());
    off.add(0, 0, 0.0, first, camera(), mrpt::poses::CPose3D());
    for (uint64_t k = 1; k <= 3; ++k)
        off.add(k, k, static_cast<double>(k), bare, camera(), mrpt::poses::CPose3D());
    EXPECT_EQ(off.pruneFreePoints(), 0U);
}

TEST(SemanticMapBuilder, NearAMoverOnlyWhatTwoKeyframesSawEntersTheMaps)
{
    // Keyframe 0: patch A 1 m in front, right beside pixels the dynamic mask caught (a person),
    // and patch B 1 m in front, 0.4 m away from them. The next keyframe either does not see
    // that part of the view (no depth there: A was seen once, as a missed part of a walking
    // person is), or sees A again where it was: 20 frames later (a static surface beside the
    // person), or 5 frames later (less than confirm_span_s: a person there would not have moved).
    const maps::BackProjector::Images first = patchesBesideAMover();
    // A and the mover not seen.
    const maps::BackProjector::Images elsewhere =
        withDepth(bareWall(), cv::Rect(28, 10, 22, 30), 0.0f);
    const maps::BackProjector::Images again = patchesWithoutTheMover();
    const auto count = [](const std::vector<Eigen::Vector3f>& pts, float xMin, float xMax)
    {
        size_t n = 0;
        for (const auto& q : pts)
            n += q.z() < 1.5f && q.x() >= xMin && q.x() < xMax ? 1 : 0;
        return n;
    };
    const auto points = [](const maps::CSemanticPointsMap& m)
    {
        std::vector<Eigen::Vector3f> out;
        for (const auto& q : m.points())
            out.push_back(q.position);
        return out;
    };
    const auto voxels = [](const maps::CSemanticOctoMap& m)
    {
        std::vector<Eigen::Vector3f> out;
        for (const auto& v : m.occupiedVoxels())
            out.push_back(v.centre);
        return out;
    };
    for (const auto& [seenAgain, frame] : {std::pair{false, 20}, {true, 20}, {true, 5}})
    {
        const bool seenTwice = seenAgain && frame >= 15;
        mapping::MapBuilderParameters p;
        p.prune_near_movers = 0.1;
        ASSERT_EQ(p.confirm_span_s, 0.5);
        mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
        b.add(0, 0, 0.0, first, camera(), mrpt::poses::CPose3D());
        b.add(1, static_cast<uint64_t>(frame), frame / 30.0, seenAgain ? again : elsewhere,
              camera(), mrpt::poses::CPose3D());
        const size_t a = count(points(b.pointsMap()), -0.2f, 0.05f);
        const size_t boxB = count(points(b.pointsMap()), -1.0f, -0.35f);
        const size_t aVoxels = count(voxels(b.octoMap()), -0.2f, 0.05f);
        const size_t wall = b.pointsMap().size() - a - boxB;
        ASSERT_GT(a, 20U);
        ASSERT_GT(boxB, 20U);
        ASSERT_GT(aVoxels, 0U);
        // At the end of a run, re-anchoring at the final poses (unchanged here) applies it.
        const auto r = b.reanchor([](const mapping::KeyFrameContribution&)
                                  { return std::optional<mrpt::poses::CPose3D>(); });
        const size_t dropped = r.unconfirmed;
        EXPECT_EQ(r.rebuilt, !seenTwice);
        EXPECT_EQ(b.dropUnconfirmedNearMovers(), dropped) << "the same test, the same points";
        EXPECT_EQ(count(points(b.pointsMap()), -0.2f, 0.05f), seenTwice ? a : 0U) << seenTwice;
        EXPECT_EQ(count(voxels(b.octoMap()), -0.2f, 0.05f), seenTwice ? aVoxels : 0U) << seenTwice;
        EXPECT_EQ(seenTwice, dropped == 0U) << dropped;
        EXPECT_EQ(count(points(b.pointsMap()), -1.0f, -0.35f), boxB) << "far from the mover";
        EXPECT_EQ(b.pointsMap().size() - count(points(b.pointsMap()), -1.0f, 0.05f), wall);
    }
}

TEST(SemanticMapBuilder, APersonBackAtTheSamePlaceDoesNotConfirmWhatWasMissedOfThem)
{
    // Keyframes 0 and 1, 20 frames apart, both see patch A right beside the pixels the dynamic
    // mask caught: a person who walked away and came back (or turned round), with a part of
    // them that segmentation missed (A) at the same place both times. Two keyframes spanning
    // confirm_span_s would confirm it; neither saw the place clear of its own movers, so A goes.
    // With the clear test off (confirm_clear_distance 0) A stays. B, 0.4 m from the mover, and
    // the wall stay either way.
    const maps::BackProjector::Images withPerson = patchesBesideAMover();
    for (const double clearDistance : {0.1, 0.0})
    {
        mapping::MapBuilderParameters p;
        p.prune_near_movers = 0.1;
        p.confirm_clear_distance = clearDistance;
        ASSERT_EQ(p.confirm_span_s, 0.5);
        mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
        b.add(0, 0, 0.0, withPerson, camera(), mrpt::poses::CPose3D());
        b.add(1, 20, 20 / 30.0, withPerson, camera(), mrpt::poses::CPose3D());
        const PatchCounts before = countPatches(b.pointsMap());
        ASSERT_GT(before.a, 20U);
        ASSERT_GT(before.b, 20U);
        const size_t dropped = b.dropUnconfirmedNearMovers();
        const bool clearTest = clearDistance > 0.0;
        const PatchCounts after = countPatches(b.pointsMap());
        EXPECT_EQ(after.a, clearTest ? 0U : before.a) << clearDistance;
        EXPECT_EQ(dropped > 0U, clearTest) << dropped;
        EXPECT_EQ(after.b, before.b) << "far from the mover";
        EXPECT_EQ(after.wall, before.wall);
    }
}

TEST(SemanticMapBuilder, AClearViewConfirmsOnlyThePlaceItSaw)
{
    // Keyframes 0 and 1, 20 frames apart, both see patch A (1 m away) right beside a mover,
    // neither clear of it: a person's missed part, seen twice. Keyframe 2, 20 frames later,
    // sees no mover and a patch at A's pixels `behind` m behind A. 3 cm behind, it saw the same
    // surface clear, and A stays. 8 cm behind (still within the 27 voxels of 5 cm around A),
    // it saw another surface: its clear view must not confirm A, and A goes. The see-through
    // test is off, so only the confirmation decides.
    for (const float behind : {0.03f, 0.08f})
    {
        mapping::MapBuilderParameters p;
        p.prune_near_movers = 0.1;
        p.see_through_margin = 0.0;
        ASSERT_DOUBLE_EQ(p.confirm_radius, 0.05);
        ASSERT_GT(p.confirm_clear_distance, 0.15) << "the mover is within it of A";
        mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
        b.add(0, 0, 0.0, patchesBesideAMover(), camera(), mrpt::poses::CPose3D());
        b.add(1, 20, 20 / 30.0, patchesBesideAMover(), camera(), mrpt::poses::CPose3D());
        maps::BackProjector::Images clear =
            withDepth(bareWall(), cv::Rect(32, 15, 8, 20), 1.0f + behind);
        b.add(2, 40, 40 / 30.0, clear, camera(), mrpt::poses::CPose3D());
        const size_t a = pointsInFront(b.pointsMap(), -0.2f, 0.05f);
        const size_t onA = a - pointsBehind(b.pointsMap(), 1.0f + behind / 2.0f);
        ASSERT_GT(onA, 20U);
        b.dropUnconfirmedNearMovers();
        const size_t onAAfter = pointsInFront(b.pointsMap(), -0.2f, 0.05f) -
                                pointsBehind(b.pointsMap(), 1.0f + behind / 2.0f);
        EXPECT_EQ(onAAfter, behind < 0.05f ? onA : 0U) << behind;
    }
}

TEST(SemanticMapBuilder, WhatAPersonLeftGoesOnceTheNewestViewOfItsPlaceSeesThrough)
{
    // Keyframes 0 and 1, 20 frames apart, both see patch A right beside the pixels the dynamic
    // mask caught (a person, A a part of them segmentation missed); with the clear test off,
    // they confirm A. Keyframe 2, 20 frames later, either sees the bare wall 1 m behind where A
    // was (the person left), or sees A again with the mover gone (A is static), or has no depth
    // there. Only the first drops A, and only with see_through_margin > 0 (the default). B,
    // which no mover was near, is seen through in the first case too, and stays: the test is
    // near movers only.
    const maps::BackProjector::Images withPerson = patchesBesideAMover();
    const maps::BackProjector::Images bare = bareWall();
    const maps::BackProjector::Images again = patchesWithoutTheMover();
    // No depth where A and the mover were.
    const maps::BackProjector::Images unseen = withDepth(bare, cv::Rect(28, 10, 22, 30), 0.0f);
    enum class Newest
    {
        Bare,
        Again,
        Unseen
    };
    ASSERT_GT(mapping::MapBuilderParameters().see_through_margin, 0.0) << "on by default";
    for (const double margin : {mapping::MapBuilderParameters().see_through_margin, 0.0})
    {
        for (const Newest newest : {Newest::Bare, Newest::Again, Newest::Unseen})
        {
            mapping::MapBuilderParameters p = nearMoversWithoutClearTest();
            p.see_through_margin = margin;
            mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
            b.add(0, 0, 0.0, withPerson, camera(), mrpt::poses::CPose3D());
            b.add(1, 20, 20 / 30.0, withPerson, camera(), mrpt::poses::CPose3D());
            const maps::BackProjector::Images& last =
                newest == Newest::Bare ? bare : (newest == Newest::Again ? again : unseen);
            b.add(2, 40, 40 / 30.0, last, camera(), mrpt::poses::CPose3D());
            const PatchCounts before = countPatches(b.pointsMap());
            ASSERT_GT(before.a, 20U);
            ASSERT_GT(before.b, 20U);
            const bool gone = margin > 0.0 && newest == Newest::Bare;
            const auto r = b.reanchor([](const mapping::KeyFrameContribution&)
                                      { return std::optional<mrpt::poses::CPose3D>(); });
            const PatchCounts after = countPatches(b.pointsMap());
            EXPECT_EQ(after.a, gone ? 0U : before.a) << margin << " " << static_cast<int>(newest);
            EXPECT_EQ(r.unconfirmed, 0U) << "two keyframes 20 frames apart confirm A";
            EXPECT_EQ(r.seenThrough > 0U, gone) << r.seenThrough;
            EXPECT_EQ(r.rebuilt, gone);
            EXPECT_EQ(after.b, before.b) << "no mover near B";
            EXPECT_EQ(after.wall, before.wall);
        }
    }
}

TEST(SemanticMapBuilder, APersonBackInFrontOfAPlaceSeenThroughDoesNotBringBackWhatWasLeft)
{
    // Keyframe 0 (frame 0) sees patch A 1 m in front of the wall, beside pixels the dynamic mask
    // caught: A is a part of a walking person that segmentation missed. Keyframe 1 (frame 20)
    // sees the bare wall through A's place. Keyframe 2 (frame 40) sees a surface 4 cm in front
    // of A's place, within see_through_margin (a person back there whom its segmentation
    // missed too), and optionally keyframe 3 (frame 60) sees it again. The newest view alone
    // sees a surface at A and keeps A; with see_through_majority, keyframe 0's A goes when the
    // views after it saw through its place at least as often as they saw a surface there (one
    // each), and stays when more of them saw the surface (one through, two at it). What
    // keyframes 2 and 3 put there themselves, and the wall, stay either way.
    const maps::BackProjector::Images withPerson = patchesBesideAMover();
    const maps::BackProjector::Images bare = bareWall();
    const maps::BackProjector::Images back = withDepth(bare, cv::Rect(32, 15, 8, 20), 0.96f);
    const auto count = [](const maps::CSemanticPointsMap& m, float zMin, float zMax)
    {
        size_t n = 0;  // at A's place (x -0.1 .. 0 m), B (x -0.5 .. -0.39 m) left out
        for (const auto& q : m.points())
            n += q.position.z() >= zMin && q.position.z() < zMax && q.position.x() > -0.2f ? 1 : 0;
        return n;
    };
    ASSERT_TRUE(mapping::MapBuilderParameters().see_through_majority) << "on by default";
    for (const bool majority : {true, false})
    {
        for (const int backViews : {1, 2})
        {
            mapping::MapBuilderParameters p = nearMoversWithoutClearTest();
            p.see_through_majority = majority;
            mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
            b.add(0, 0, 0.0, withPerson, camera(), mrpt::poses::CPose3D());
            b.add(1, 20, 20 / 30.0, bare, camera(), mrpt::poses::CPose3D());
            for (int k = 2; k < 2 + backViews; ++k)
                b.add(static_cast<uint64_t>(k), 20U * static_cast<uint64_t>(k), 20 * k / 30.0, back,
                      camera(), mrpt::poses::CPose3D());
            const size_t a = count(b.pointsMap(), 0.99f, 1.01f);
            const size_t front = count(b.pointsMap(), 0.95f, 0.97f);
            const size_t wall = count(b.pointsMap(), 1.5f, 2.5f);
            ASSERT_GT(a, 20U);
            ASSERT_GT(front, 20U);
            const auto r = b.reanchor([](const mapping::KeyFrameContribution&)
                                      { return std::optional<mrpt::poses::CPose3D>(); });
            const bool gone = majority && backViews == 1;
            EXPECT_EQ(count(b.pointsMap(), 0.99f, 1.01f), gone ? 0U : a)
                << "majority " << majority << ", " << backViews << " views back";
            EXPECT_EQ(r.seenThrough > 0U, gone) << r.seenThrough;
            EXPECT_EQ(count(b.pointsMap(), 0.95f, 0.97f), front);
            EXPECT_EQ(count(b.pointsMap(), 1.5f, 2.5f), wall);
        }
    }
}

TEST(SemanticMapBuilder, APersonWhoStaysWhereKeyframesSawThemLeavesTheMaps)
{
    // A person stands 0.2 m in front of the wall (30 x 40 px at 1.8 m: 17 x 23 cm, a narrow
    // camera so that body samples every 4 px lie 2.3 cm apart) for four keyframes, 20 frames
    // apart. Keyframes 0 and 3 label them person, spilling 2 px onto the wall around them, and
    // Algorithm 1 drops them; keyframes 1 and 2 miss them (a back seen from behind): without the
    // body test the two confirm each other, seeing the place clear of movers of their own, and
    // the person stays in both maps. With it, everything within 4 cm of where keyframes 0 and 3
    // saw their body goes; eroding the labels by the spill keeps the wall around them, without
    // erosion the spilled labels (at the wall's depth, within 0.4 m of the person's) take wall
    // points with them. A body seen by keyframe 0 alone (keyframe 3 misses it too) is not a
    // person who stayed, as a walking person's outline is not: nothing goes.
    const core::PinholeCamera narrow = test::centredCamera(80, 60, 320.0);
    const cv::Rect person(20, 10, 30, 40);
    maps::BackProjector::Images seen = wall();
    seen.dynamicMask.setTo(0);
    seen.labels.setTo(0);
    seen.depth(person).setTo(1.8f);
    seen.labels(cv::Rect(18, 8, 34, 44)).setTo(15);
    seen.dynamicMask(person).setTo(255);
    maps::BackProjector::Images missed = seen;
    missed.labels = cv::Mat(seen.labels.size(), CV_8UC1, cv::Scalar(0));
    missed.dynamicMask = cv::Mat(seen.dynamicMask.size(), CV_8UC1, cv::Scalar(0));
    struct Result
    {
        size_t person = 0, personVoxels = 0, wall = 0, onBody = 0;
    };
    const auto run = [&](double radius, int erosion, bool seenAgain)
    {
        mapping::MapBuilderParameters p;
        p.movable_body_radius = radius;
        p.movable_body_erosion = erosion;
        mapping::SemanticMapBuilder b(p, core::LabelSet::pascalVoc());
        b.add(0, 0, 0.0, seen, narrow, mrpt::poses::CPose3D());
        b.add(1, 20, 20 / 30.0, missed, narrow, mrpt::poses::CPose3D());
        b.add(2, 40, 40 / 30.0, missed, narrow, mrpt::poses::CPose3D());
        b.add(3, 60, 60 / 30.0, seenAgain ? seen : missed, narrow, mrpt::poses::CPose3D());
        const auto r = b.reanchor([](const mapping::KeyFrameContribution&)
                                  { return std::optional<mrpt::poses::CPose3D>(); });
        Result out;
        for (const auto& q : b.pointsMap().points())
            (q.position.z() < 1.9f ? out.person : out.wall)++;
        for (const auto& v : b.octoMap().occupiedVoxels())
            out.personVoxels += v.centre.z() < 1.9f ? 1 : 0;
        out.onBody = r.onBody;
        return out;
    };
    const Result off = run(0.0, 2, true);
    ASSERT_GT(off.person, 50U) << "keyframes 1 and 2 confirm what they saw of the person";
    ASSERT_GT(off.personVoxels, 5U);
    EXPECT_EQ(off.onBody, 0U);
    const Result on = run(0.04, 2, true);
    EXPECT_EQ(on.person, 0U);
    EXPECT_EQ(on.personVoxels, 0U);
    EXPECT_GE(on.onBody, off.person);
    EXPECT_EQ(on.wall, off.wall) << "the wall around the person stays";
    const Result unEroded = run(0.04, 0, true);
    EXPECT_EQ(unEroded.person, 0U);
    EXPECT_LT(unEroded.wall, off.wall) << "the labels spilled onto the wall take it with them";
    const Result once = run(0.04, 2, false);
    EXPECT_EQ(once.onBody, 0U);
    EXPECT_EQ(once.person, run(0.0, 2, false).person);
    EXPECT_GT(once.person, 50U);
}

TEST(SemanticMapBuilder, ALabelFileOfThirtyClassesKeepsClass25AndItsColour)
{
    // A label file beyond PASCAL VOC's 21 classes: class 25 must reach both maps (the octomap's
    // distribution has one entry per class of the file) and be drawn in the file's colour.
    const std::string path = ::testing::TempDir() + "thirty_classes.csv";
    {
        std::ofstream csv(path);
        csv << "id,name,r,g,b,dynamic_prior\n";
        for (int i = 0; i < 30; i++)
            csv << i << ",class" << i << "," << (i == 25 ? 201 : i) << "," << (i == 25 ? 17 : i)
                << "," << (i == 25 ? 99 : i) << ",0\n";
    }
    const auto labels = core::LabelSet::loadCsv(path);
    ASSERT_EQ(labels.size(), 30u);

    maps::BackProjector::Images im = wall();
    im.labels.setTo(25);
    im.dynamicMask.setTo(0);
    mapping::MapBuilderParameters p;
    mapping::SemanticMapBuilder b(p, labels);
    b.add(0, 0, 1.0, im, camera(), mrpt::poses::CPose3D());

    EXPECT_EQ(b.octoMap().insertionOptions.label_count, 30);
    const auto points = b.pointsMap().points();
    ASSERT_FALSE(points.empty());
    for (const auto& pt : points)
        ASSERT_EQ(pt.label, 25);
    const auto voxels = b.octoMap().occupiedVoxels();
    ASSERT_FALSE(voxels.empty());
    for (const auto& v : voxels)
        ASSERT_EQ(v.label, 25);

    // Coloured by class, both maps draw class 25 as the file says (r 201, g 17, b 99).
    for (const mrpt::maps::CMetricMap* map :
         {static_cast<const mrpt::maps::CMetricMap*>(&b.pointsMap()),
          static_cast<const mrpt::maps::CMetricMap*>(&b.octoMap())})
    {
        mrpt::opengl::CSetOfObjects scene;
        map->getVisualizationInto(scene);
        const auto cloud = scene.getByClass<mrpt::opengl::CPointCloudColoured>();
        ASSERT_TRUE(cloud);
        ASSERT_GT(cloud->size(), 0u);
        for (size_t i = 0; i < cloud->size(); i++)
        {
            const mrpt::img::TColor c = cloud->getPointColor(i);
            ASSERT_EQ(c.R, 201);
            ASSERT_EQ(c.G, 17);
            ASSERT_EQ(c.B, 99);
        }
    }
}

TEST(MapBuilderParameters, MovableBodyValuesOutOfRangeNameTheKey)
{
    for (const auto& [key, value] : {std::pair{"movable_body_radius", "-0.1"},
                                     {"movable_body_erosion", "-1"},
                                     {"movable_body_prior", "-1"}})
    {
        mrpt::config::CConfigFileMemory cfg;
        cfg.write("map", key, value);
        mapping::MapBuilderParameters p;
        try
        {
            p.loadFromConfigFile(cfg, "map");
            ADD_FAILURE() << key << " = " << value << " was accepted";
        }
        catch (const core::InputError& e)
        {
            EXPECT_NE(std::string(e.what()).find(std::string("[map] ") + key), std::string::npos)
                << e.what();
        }
    }
}
