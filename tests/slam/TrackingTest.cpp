// RGB-D tracking on rendered sequences with exact ground truth: accuracy, repeatability,
// losing and relocalising across a blank stretch, and the outside feature mask.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <opencv2/core.hpp>
#include <set>

#include "SyntheticSequence.h"
#include "TestData.h"
#include "smap/eval/AbsoluteTrajectoryError.h"
#include "smap/slam/KeyFrame.h"
#include "smap/slam/Map.h"
#include "smap/slam/MapPoint.h"
#include "smap/slam/ProjectionSearch.h"
#include "smap/slam/Relocalisation.h"
#include "smap/slam/RgbdSlam.h"

using namespace smap;

namespace
{
slam::LocalMappingParameters deterministic()
{
    slam::LocalMappingParameters p;
    p.threaded = false;
    return p;
}

const test::RenderedSequence& staticXyz()
{
    // Rendered once for the whole suite (about 5 s).
    static const test::RenderedSequence seq = test::renderSequence("static_xyz", 150);
    return seq;
}

double ateRmse(const core::Trajectory& gt, const core::Trajectory& est)
{
    return eval::computeAte(gt, est).translation.rmse;
}

/// Feeds every frame of `seq`, expects each to get a pose, finishes; the frames' trajectory.
core::Trajectory trackAll(slam::RgbdSlam& slam, const test::RenderedSequence& seq)
{
    size_t withPose = 0;
    for (const auto& f : seq.frames)
        withPose += slam::hasPose(slam.process(f).status) ? 1 : 0;
    slam.finish();
    EXPECT_EQ(withPose, seq.frames.size());
    return slam.trajectory();
}

/// One map point per keypoint of `frame` with depth, observed by `kf` (the frame's keyframe).
std::vector<std::shared_ptr<slam::MapPoint>> addDepthPoints(slam::Map& map, slam::KeyFrame& kf,
                                                            const slam::Frame& frame)
{
    std::vector<std::shared_ptr<slam::MapPoint>> points;
    for (size_t i = 0; i < frame.size(); ++i)
    {
        if (!frame.features.hasDepth(i))
            continue;
        const auto& p = frame.features.undistorted[i];
        const Eigen::Vector3d X_cam = frame.camera.unproject(p.x, p.y, frame.features.depth[i]);
        auto mp = map.createPoint(frame.T_cam_world.inverse() * X_cam, &kf);
        mp->addObservation(&kf, i);
        kf.points[i] = mp;
        mp->computeDistinctiveDescriptor();
        mp->updateNormalAndDepth();
        points.push_back(mp);
    }
    return points;
}

/// A map with one keyframe: staticXyz's frame 0 at the origin, with a point per keypoint with
/// depth (the relocalisation and projection tests start from it).
struct OneKeyFrameMap
{
    slam::RgbdSlam slam{features::OrbParameters{}, slam::TrackerParameters{}, deterministic()};
    slam::Map map;
    slam::Frame first;
    std::shared_ptr<slam::KeyFrame> keyframe;
    std::vector<std::shared_ptr<slam::MapPoint>> points;

    OneKeyFrameMap() : first(slam.prepare(staticXyz().frames[0]))
    {
        first.T_cam_world = Eigen::Isometry3d::Identity();
        keyframe = map.createKeyFrame(first);
        points = addDepthPoints(map, *keyframe, first);
    }

    /// staticXyz's frame `index` as a lost frame, with thumbnails that rank `lookAlikes`
    /// first and the keyframe with points last.
    slam::Frame lostFrame(size_t index,
                          const std::vector<std::shared_ptr<slam::KeyFrame>>& lookAlikes)
    {
        slam::Frame f = slam.prepare(staticXyz().frames[index]);
        for (const auto& kf : lookAlikes)
            kf->thumbnail = f.thumbnail.clone();
        keyframe->thumbnail = -f.thumbnail;
        return f;
    }
};
}  // namespace

TEST(RgbdSlam, StaticSequenceIsTrackedToBetterThanOneCentimetre)
{
    const auto& seq = staticXyz();
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    const auto traj = trackAll(slam, seq);
    ASSERT_EQ(traj.size(), seq.frames.size());
    EXPECT_LT(ateRmse(seq.groundTruth, traj), 0.01);
    EXPECT_GT(slam.numKeyFrames(), 1U);
    EXPECT_GT(slam.numPoints(), 200U);
    // Keyframe trajectory is a subset of the frames' and as accurate.
    const auto kfs = slam.keyFrameTrajectory();
    ASSERT_GE(kfs.size(), 2U);
    EXPECT_LT(ateRmse(seq.groundTruth, kfs), 0.01);
}

TEST(RgbdSlam, HalfResolutionSequenceIsTrackedToBetterThanTwoCentimetres)
{
    // Nothing in extraction or tracking may assume 640x480. At 320x240 (f = 262.5) a pixel spans
    // twice the angle and the pyramid's top level is 67x56 px: these 90 frames track to 10.0 mm
    // (the full-size 300-frame sequence to 3.2 mm, at 320x240 to 9.5 mm; `smap-synth --size`).
    const auto seq =
        test::renderSequence("static_xyz", 90, 1, test::centredCamera(320, 240, 262.5));
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    const auto traj = trackAll(slam, seq);
    ASSERT_EQ(traj.size(), seq.frames.size());
    EXPECT_LT(ateRmse(seq.groundTruth, traj), 0.02);
    EXPECT_GT(slam.numPoints(), 200U);
}

TEST(RgbdSlam, DeterministicModeGivesIdenticalTrajectories)
{
    const auto& seq = staticXyz();
    std::vector<core::Trajectory> runs;
    for (int r = 0; r < 2; ++r)
    {
        slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
        for (size_t i = 0; i < 60; ++i)
            slam.process(seq.frames[i]);
        runs.push_back(slam.trajectory());
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    for (size_t i = 0; i < runs[0].size(); ++i)
        EXPECT_EQ(runs[0][i].T_world_cam.asString(), runs[1][i].T_world_cam.asString()) << i;
}

// The xyz motion comes back to where it was: with loops looked for 40 frames back, loop closing
// verifies revisits; each agrees with the ground truth's relative pose, the trajectory stays as
// accurate, and with both threads off two runs are identical.
TEST(LoopClosing, RevisitsAreVerifiedTrueAndDeterministic)
{
    const auto& seq = staticXyz();
    slam::LoopClosingParameters loop;
    loop.threaded = false;
    loop.min_age_s = 40.0 / 30.0;  // 40 frames
    loop.min_keyframes = 3;
    std::vector<core::Trajectory> runs;
    for (int r = 0; r < 2; ++r)
    {
        slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic(),
                            loop);
        runs.push_back(trackAll(slam, seq));
        const auto st = slam.loopClosingStats();
        EXPECT_GT(st.keyframesChecked, 5U);
        ASSERT_FALSE(st.closures.empty()) << "no revisit verified";
        for (const auto& c : st.closures)
        {
            EXPECT_GE(c.frameId, c.loopFrameId + 40);
            EXPECT_GE(c.projectedMatches, loop.min_projected_matches);
            const auto& gtLoop = seq.groundTruth[c.loopFrameId].T_world_cam;
            const auto& gtKf = seq.groundTruth[c.frameId].T_world_cam;
            // T_loop_keyframe = T_cam_loop * T_cam_kf^-1 = T_world_loop^-1 * T_world_kf.
            const mrpt::poses::CPose3D truth = gtKf - gtLoop;
            const mrpt::poses::CPose3D est = slam::toCPose3D(c.T_loop_keyframe);
            const mrpt::poses::CPose3D err = est - truth;
            EXPECT_LT(err.norm(), 0.03) << "loop " << c.frameId << " -> " << c.loopFrameId;
        }
        EXPECT_LT(ateRmse(seq.groundTruth, runs.back()), 0.01);
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    for (size_t i = 0; i < runs[0].size(); ++i)
        EXPECT_EQ(runs[0][i].T_world_cam.asString(), runs[1][i].T_world_cam.asString()) << i;
}

TEST(RgbdSlam, ThreadedLocalMappingTracksAsWell)
{
    const auto& seq = staticXyz();
    slam::LocalMappingParameters p;
    p.threaded = true;
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, p);
    for (const auto& f : seq.frames)
        slam.process(f);
    slam.finish();
    EXPECT_EQ(slam.trajectory().size(), seq.frames.size());
    EXPECT_LT(ateRmse(seq.groundTruth, slam.trajectory()), 0.015);
}

// Frames 50..69 are blank (flat grey, no depth): tracking must report them lost without a
// pose, then relocalise when the view returns and stay accurate.
TEST(RgbdSlam, BlankStretchIsLostThenRelocalised)
{
    const auto& seq = staticXyz();
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    std::vector<slam::TrackingStatus> status;
    for (size_t i = 0; i < seq.frames.size(); ++i)
    {
        core::RgbdFrame f = seq.frames[i];
        if (i >= 50 && i < 70)
        {
            f.colour = cv::Mat(f.colour.size(), CV_8UC3, cv::Scalar(120, 120, 120));
            f.depth = cv::Mat::zeros(f.depth.size(), CV_32FC1);
        }
        status.push_back(slam.process(f).status);
    }
    slam.finish();
    for (size_t i = 50; i < 70; ++i)
        EXPECT_EQ(status[i], slam::TrackingStatus::Lost) << i;
    size_t firstBack = 0;
    for (size_t i = 70; i < status.size() && firstBack == 0; ++i)
        if (status[i] == slam::TrackingStatus::Relocalised)
            firstBack = i;
    ASSERT_GT(firstBack, 0U) << "never relocalised";
    EXPECT_LT(firstBack, 100U);
    for (size_t i = firstBack + 1; i < status.size(); ++i)
        EXPECT_EQ(status[i], slam::TrackingStatus::Ok) << i;
    const auto traj = slam.trajectory();
    EXPECT_EQ(traj.size(), seq.frames.size() - 20 - (firstBack - 70));
    EXPECT_LT(ateRmse(seq.groundTruth, traj), 0.015);
}

// After frame 29 the camera is carried into a scene the map has never seen (another seed's
// textures): relocalisation cannot succeed there. With re-anchoring (after 3 lost frames) a new
// part of the map starts at the predicted pose and the rest is tracked, accurately relative to
// itself; without it every later frame is lost. The new part never meets the first again, and
// poses more frames (47 against 30): at the end it stays and the first part's frames lose
// their pose.
TEST(RgbdSlam, UnknownSceneIsReanchoredAfterAFewLostFrames)
{
    constexpr size_t kSwitch = 30;
    const auto& first = staticXyz();
    static const test::RenderedSequence other = test::renderSequence("static_xyz", 50, 7);
    std::vector<core::RgbdFrame> frames(first.frames.begin(), first.frames.begin() + kSwitch);
    core::Trajectory otherTruth;
    for (size_t k = 0; k < other.frames.size(); ++k)
    {
        core::RgbdFrame f = other.frames[k];
        f.timestamp = first.frames[kSwitch - 1].timestamp + static_cast<double>(k + 1) / 30.0;
        f.index = kSwitch + k;
        frames.push_back(f);
        otherTruth.push_back({f.timestamp, other.groundTruth[k].T_world_cam});
    }
    for (const int after : {3, 0})
    {
        slam::TrackerParameters tp;
        tp.reanchor_after_s = after / 30.0;  // frames at 30 frames/s
        slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
        std::vector<slam::TrackingStatus> status;
        status.reserve(frames.size());
        for (const auto& f : frames)
            status.push_back(slam.process(f).status);
        slam.finish();
        for (size_t i = 1; i < kSwitch; ++i)
            ASSERT_EQ(status[i], slam::TrackingStatus::Ok) << i;
        if (after == 0)
        {
            for (size_t i = kSwitch; i < frames.size(); ++i)
                EXPECT_EQ(status[i], slam::TrackingStatus::Lost) << i;
            EXPECT_EQ(slam.trajectory().size(), kSwitch);
            EXPECT_EQ(slam.mapPartStats().started, 0U);
            continue;
        }
        for (size_t i = kSwitch; i < kSwitch + 3; ++i)
            EXPECT_EQ(status[i], slam::TrackingStatus::Lost) << i;
        EXPECT_EQ(status[kSwitch + 3], slam::TrackingStatus::Reanchored);
        for (size_t i = kSwitch + 4; i < frames.size(); ++i)
            EXPECT_EQ(status[i], slam::TrackingStatus::Ok) << i;
        const auto parts = slam.mapPartStats();
        EXPECT_EQ(parts.started, 1U);
        EXPECT_EQ(parts.merged, 0U);
        EXPECT_EQ(parts.discarded, 1U) << "the first part, with fewer frames";
        const core::Trajectory kept = slam.trajectory();
        ASSERT_EQ(kept.size(), frames.size() - kSwitch - 3);
        EXPECT_GE(kept.front().timestamp, frames[kSwitch + 3].timestamp - 1e-6);
        EXPECT_LT(ateRmse(otherTruth, kept), 0.01);
        for (const auto& p : slam.keyFrameTrajectory())
            EXPECT_GE(p.timestamp, frames[kSwitch + 3].timestamp - 1e-6) << "a dropped keyframe";
    }
}

namespace
{
/// `f` with its colours inverted where `region` is set (all of it when empty): the same
/// geometry and corners, but ORB descriptors that match nothing of the original.
core::RgbdFrame inverted(const core::RgbdFrame& f, const cv::Rect& region = {})
{
    core::RgbdFrame out = f;
    out.colour = f.colour.clone();
    const cv::Rect r = region.area() > 0 ? region : cv::Rect(0, 0, f.colour.cols, f.colour.rows);
    cv::Mat roi = out.colour(r);
    cv::bitwise_not(roi, roi);
    return out;
}
}  // namespace

// A part of the map that meets the first again is merged into it. Frames 50-59 are blank
// (lost); from 60 the colours are inverted, a view no keyframe can place, so that after 3 lost
// frames the map is re-anchored at a pose extrapolated 3 frames from frame 49 while the camera
// moved on for 11. From 75 the right half is shown as it is: the tracker still follows the new
// part on the left half, and the right half places the frame in the first part, which joins
// the two. Every frame but the lost ones then has a pose in the first part's frame.
TEST(RgbdSlam, AReanchoredPartMergesWhereItMeetsTheMapAgain)
{
    constexpr size_t kBlank = 50, kInverted = 60, kHalf = 75, kEnd = 100;
    const auto& seq = staticXyz();
    slam::TrackerParameters tp;
    tp.reanchor_after_s = 3.0 / 30.0;  // 3 frames
    slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
    std::vector<slam::TrackingResult> results;
    for (size_t i = 0; i < kEnd; ++i)
    {
        core::RgbdFrame f = seq.frames[i];
        const int w = f.colour.cols, h = f.colour.rows;
        if (i >= kBlank && i < kInverted)
        {
            f.colour = cv::Mat(f.colour.size(), CV_8UC3, cv::Scalar(120, 120, 120));
            f.depth = cv::Mat::zeros(f.depth.size(), CV_32FC1);
        }
        else if (i >= kInverted)
            f = inverted(f, i < kHalf ? cv::Rect() : cv::Rect(0, 0, w / 2, h));
        results.push_back(slam.process(f));
    }
    slam.finish();
    size_t reanchored = 0;
    for (size_t i = kInverted; i < kEnd && reanchored == 0; ++i)
        if (results[i].status == slam::TrackingStatus::Reanchored)
            reanchored = i;
    ASSERT_GT(reanchored, 0U) << "never re-anchored";
    // The map's frame is the first camera's. The check bites: the new part started well away
    // from the truth.
    const auto truth = [&](size_t i)
    { return seq.groundTruth[i].T_world_cam - seq.groundTruth[0].T_world_cam; };
    const mrpt::poses::CPose3D guess = slam::toCPose3D(results[reanchored].T_world_cam);
    ASSERT_GT((guess - truth(reanchored)).norm(), 0.03);
    const auto parts = slam.mapPartStats();
    EXPECT_EQ(parts.started, 1U);
    EXPECT_EQ(parts.merged, 1U);
    EXPECT_EQ(parts.discarded, 0U);
    for (size_t i = reanchored + 1; i < kEnd; ++i)
        EXPECT_EQ(results[i].status, slam::TrackingStatus::Ok) << i;
    const core::Trajectory traj = slam.trajectory();
    EXPECT_EQ(traj.size(), kEnd - (reanchored - kBlank));
    EXPECT_LT(ateRmse(seq.groundTruth, traj), 0.01);
    // The merged part in the first part's frame: the re-anchored frame's final pose.
    const auto poses = slam.framePoses();
    ASSERT_TRUE(poses.count(reanchored));
    EXPECT_LT((poses.at(reanchored) - truth(reanchored)).norm(), 0.01);
}

TEST(RgbdSlam, TexturelessStartWaitsThenInitialises)
{
    const auto& seq = staticXyz();
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    core::RgbdFrame blank = seq.frames[0];
    blank.colour = cv::Mat(blank.colour.size(), CV_8UC3, cv::Scalar(0, 0, 0));
    EXPECT_EQ(slam.process(blank).status, slam::TrackingStatus::NotInitialised);
    EXPECT_EQ(slam.process(seq.frames[1]).status, slam::TrackingStatus::Initialised);
    EXPECT_EQ(slam.process(seq.frames[2]).status, slam::TrackingStatus::Ok);
}

// The tracker's outside mask: features under a zero mask never become or match map points.
TEST(RgbdSlam, MaskedFeaturesNeverEnterTheMap)
{
    const auto& seq = staticXyz();
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    const auto& cam = seq.frames[0].camera;
    cv::Mat mask(cam.height, cam.width, CV_8UC1, cv::Scalar(255));
    mask(cv::Rect(0, 0, cam.width / 2, cam.height)).setTo(0);  // left half masked out
    const auto r = slam.process(seq.frames[0], mask);
    ASSERT_EQ(r.status, slam::TrackingStatus::Initialised);
    // Every map point projects into the right half of the first (world) camera.
    const auto pts = slam.mapPointPositions();
    ASSERT_GT(pts.size(), 100U);
    for (const auto& p : pts)
        EXPECT_GE(cam.project(p).x(), cam.width / 2.0 - 1.0);

    // All weights zero: nothing to initialise from.
    slam::RgbdSlam slam2(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    auto f = slam2.prepare(seq.frames[0]);
    f.setWeights(std::vector<float>(f.size(), 0.0F));
    EXPECT_EQ(slam2.track(std::move(f)).status, slam::TrackingStatus::NotInitialised);
    EXPECT_TRUE(slam2.mapPointPositions().empty());

    auto g = slam2.prepare(seq.frames[0]);
    EXPECT_THROW(g.setWeights(std::vector<float>(3, 1.0F)), std::invalid_argument);
    EXPECT_THROW(g.setWeights(std::vector<float>(g.size(), 1.5F)), std::invalid_argument);
}

// Keypoints flagged as not mappable are tracked but start no map point at later keyframes.
TEST(RgbdSlam, NonMappableKeypointsStartNoMapPoints)
{
    const auto& seq = staticXyz();
    auto run = [&seq](bool mappable)
    {
        slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
        size_t afterInit = 0;
        int withPose = 0;
        for (size_t i = 0; i < 45; ++i)
        {
            auto f = slam.prepare(seq.frames[i]);
            if (i > 0)
                f.setMappable(std::vector<bool>(f.size(), mappable));
            withPose += slam::hasPose(slam.track(std::move(f)).status) ? 1 : 0;
            if (i == 0)
                afterInit = slam.numPointsCreated();
        }
        slam.finish();
        EXPECT_EQ(withPose, 45);
        EXPECT_GT(slam.numKeyFrames(), 1U) << "keyframes were made, so points could have been";
        return std::make_pair(afterInit, slam.numPointsCreated());
    };
    const auto [initAll, endAll] = run(true);
    const auto [initNone, endNone] = run(false);
    ASSERT_EQ(initAll, initNone) << "the first keyframe is not restricted";
    EXPECT_GT(endAll, initAll + 50) << "control: mappable keypoints do make new points";
    EXPECT_EQ(endNone, initNone) << "no new points after the first keyframe";

    auto g = slam::RgbdSlam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic())
                 .prepare(seq.frames[0]);
    EXPECT_THROW(g.setMappable(std::vector<bool>(3, true)), std::invalid_argument);
}

// A frame whose outside weights exclude nearly every keypoint (a filter gone wrong) fails to
// track; with fallback_weight it is tracked once more with raised weights, at the true pose.
TEST(RgbdSlam, FrameFailingWithItsWeightsIsTrackedWithRaisedWeights)
{
    const auto& seq = staticXyz();
    constexpr size_t kBad = 30;
    auto run = [&seq](double fallback)
    {
        slam::TrackerParameters tp;
        tp.fallback_weight = fallback;
        slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
        slam::TrackingResult bad;
        for (size_t i = 0; i <= kBad; ++i)
        {
            auto f = slam.prepare(seq.frames[i]);
            if (i == kBad)
            {
                std::vector<float> w(f.size(), 0.0F);
                for (size_t k = 0; k < w.size(); k += 50)
                    w[k] = 1.0F;  // 2 % of the keypoints left
                f.setWeights(w);
            }
            bad = slam.track(std::move(f));
        }
        return bad;
    };
    EXPECT_EQ(run(0.0).status, slam::TrackingStatus::Lost) << "without the fallback";
    const auto r = run(0.5);
    ASSERT_EQ(r.status, slam::TrackingStatus::Ok);
    EXPECT_EQ(r.fallback, slam::TrackingFallback::RaisedWeights);
    // The map's world is the first camera.
    const mrpt::poses::CPose3D T_first_cam =
        seq.groundTruth[kBad].T_world_cam - seq.groundTruth[0].T_world_cam;
    const mrpt::poses::CPose3D error = slam::toCPose3D(r.T_world_cam) - T_first_cam;
    EXPECT_LT(error.norm(), 0.01) << "translation error (m)";
}

// A frame whose movable-class mask covers nearly every keypoint (a stale or grown mask where
// people fill the view): raised weights leave movable keypoints out and fail; the last fallback
// also weights those the motion evidence found still, and tracks the frame at the true pose.
// Movable keypoints the motion evidence flagged stay out.
TEST(RgbdSlam, FrameCoveredByAMovableMaskIsTrackedOnItsStillKeypoints)
{
    const auto& seq = staticXyz();
    constexpr size_t kBad = 30;
    auto run = [&seq](bool stillKnown)
    {
        slam::TrackerParameters tp;
        tp.fallback_weight = 0.5;
        slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
        slam::TrackingResult bad;
        for (size_t i = 0; i <= kBad; ++i)
        {
            auto f = slam.prepare(seq.frames[i]);
            if (i == kBad)
            {
                f.movable.assign(f.size(), true);
                f.stillMovable.assign(f.size(), false);
                std::vector<float> w(f.size(), 0.0F);
                for (size_t k = 0; k < w.size(); k += 50)
                    f.movable[k] = false;  // 2 % outside the mask
                for (size_t k = 0; k < w.size(); ++k)
                {
                    w[k] = f.movable[k] ? 0.0F : 1.0F;
                    // Half the movable keypoints were found still by the motion evidence.
                    f.stillMovable[k] = stillKnown && f.movable[k] && k % 2 == 0;
                }
                f.setWeights(w);
            }
            bad = slam.track(std::move(f));
        }
        return bad;
    };
    const auto without = run(false);
    EXPECT_EQ(without.status, slam::TrackingStatus::Lost) << "movable keypoints stay out";
    EXPECT_EQ(without.fallback, slam::TrackingFallback::None);
    const auto r = run(true);
    ASSERT_EQ(r.status, slam::TrackingStatus::Ok);
    EXPECT_EQ(r.fallback, slam::TrackingFallback::StillMovable);
    const mrpt::poses::CPose3D T_first_cam =
        seq.groundTruth[kBad].T_world_cam - seq.groundTruth[0].T_world_cam;
    const mrpt::poses::CPose3D error = slam::toCPose3D(r.T_world_cam) - T_first_cam;
    EXPECT_LT(error.norm(), 0.01) << "translation error (m)";
    EXPECT_EQ(slam::toString(slam::TrackingFallback::StillMovable), "still_movable");
    EXPECT_EQ(slam::toString(slam::TrackingFallback::None), "");
}

// A fallback stage that finds a pose far from the constant-velocity prediction is not kept: the
// frame with 2 % of its keypoints weighted is the image of three frames later, stamped as the
// next frame, so the raised-weights fallback finds a pose one jump away from the prediction.
// With fallback_max_jump above the jump the frame is tracked there, below it the frame is lost;
// stamped at its own time (three frame intervals) the allowance triples and it is kept again.
TEST(RgbdSlam, FallbackPoseFarFromThePredictionIsNotKept)
{
    const auto& seq = staticXyz();
    constexpr size_t kBad = 30, kAhead = 3;
    const double jump =
        (seq.groundTruth[kBad + kAhead].T_world_cam - seq.groundTruth[kBad].T_world_cam).norm();
    ASSERT_GT(jump, 0.005) << "the camera must move for the check to bite";
    auto run = [&seq](double maxJump, bool ownTime)
    {
        slam::TrackerParameters tp;
        tp.fallback_max_jump = maxJump;
        tp.fallback_max_jump_deg = 0.0;
        tp.carried_search_s = 0.0;
        slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
        slam::TrackingResult bad;
        for (size_t i = 0; i <= kBad; ++i)
        {
            auto f = slam.prepare(seq.frames[i == kBad ? kBad + kAhead : i]);
            if (i == kBad)
            {
                if (!ownTime)
                    f.timestamp = seq.frames[kBad].timestamp;
                std::vector<float> w(f.size(), 0.0F);
                for (size_t k = 0; k < w.size(); k += 50)
                    w[k] = 1.0F;
                f.setWeights(w);
            }
            bad = slam.track(std::move(f));
        }
        return bad;
    };
    const auto kept = run(2.0 * jump, false);
    ASSERT_EQ(kept.status, slam::TrackingStatus::Ok);
    EXPECT_EQ(kept.fallback, slam::TrackingFallback::RaisedWeights);
    const mrpt::poses::CPose3D T_first_cam =
        seq.groundTruth[kBad + kAhead].T_world_cam - seq.groundTruth[0].T_world_cam;
    EXPECT_LT((slam::toCPose3D(kept.T_world_cam) - T_first_cam).norm(), 0.01)
        << "translation error (m)";
    EXPECT_EQ(run(0.5 * jump, false).status, slam::TrackingStatus::Lost) << "jumped too far";
    EXPECT_EQ(run(0.5 * jump, true).status, slam::TrackingStatus::Ok) << "three intervals passed";
}

// A first frame the outside could not vet (all weights 0) starts no map; the next one does, and
// the outside odometry linking the two then gives the first frame its pose, refined against the
// new map (or the odometry's own when the refinement finds too few inliers).
TEST(RgbdSlam, FrameBeforeTheMapIsPosedFromTheOdometryThatLinksIt)
{
    const auto& seq = staticXyz();
    constexpr size_t kSecond = 10;
    // The first camera in the map's world (the second camera), and an odometry 3 cm off it.
    const mrpt::poses::CPose3D T_second_first =
        seq.groundTruth[0].T_world_cam - seq.groundTruth[kSecond].T_world_cam;
    ASSERT_GT(T_second_first.norm(), 0.02) << "the two frames must be apart for the check to bite";
    const mrpt::poses::CPose3D odometryPose =
        T_second_first + mrpt::poses::CPose3D(0.03, 0, 0, 0, 0, 0);
    const Eigen::Isometry3d odometry_T_second_first(
        odometryPose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen());
    struct Run
    {
        slam::TrackingResult second;
        core::Trajectory trajectory;
        slam::TrackingStatus firstStatus;
    };
    auto run = [&](bool withOdometry, int minInliers)
    {
        slam::TrackerParameters tp;
        tp.min_inliers = minInliers;
        slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
        auto first = slam.prepare(seq.frames[0]);
        first.setWeights(std::vector<float>(first.size(), 0.0F));
        EXPECT_EQ(slam.track(std::move(first)).status, slam::TrackingStatus::NotInitialised);
        auto second = slam.prepare(seq.frames[kSecond]);
        if (withOdometry)
        {
            second.odometry_T_cam_earlier = odometry_T_second_first;
            second.odometryFramesBack = 1;
        }
        Run r;
        r.second = slam.track(std::move(second));
        EXPECT_EQ(r.second.status, slam::TrackingStatus::Initialised);
        EXPECT_EQ(r.second.frameId, 1U);
        slam.finish();
        EXPECT_EQ(slam.records().size(), 2U);
        r.firstStatus = slam.records().front().status;
        r.trajectory = slam.trajectory();
        return r;
    };

    const Run without = run(false, 30);
    EXPECT_EQ(without.firstStatus, slam::TrackingStatus::NotInitialised);
    EXPECT_FALSE(without.second.posedEarlierFrameId.has_value());
    ASSERT_EQ(without.trajectory.size(), 1U);
    EXPECT_EQ(without.trajectory[0].timestamp, seq.frames[kSecond].timestamp);

    const Run refined = run(true, 30);
    EXPECT_EQ(refined.firstStatus, slam::TrackingStatus::Odometry);
    EXPECT_TRUE(slam::hasPose(refined.firstStatus));
    ASSERT_TRUE(refined.second.posedEarlierFrameId.has_value());
    EXPECT_EQ(*refined.second.posedEarlierFrameId, 0U);
    ASSERT_EQ(refined.trajectory.size(), 2U);
    EXPECT_EQ(refined.trajectory[0].timestamp, seq.frames[0].timestamp);
    EXPECT_EQ(refined.trajectory[1].timestamp, seq.frames[kSecond].timestamp);
    EXPECT_LT((refined.trajectory[0].T_world_cam - T_second_first).norm(), 0.005)
        << "refined against the map, well within the odometry's 3 cm";

    // No refinement can reach this many inliers: the odometry's pose stands.
    const Run unrefined = run(true, 100000);
    ASSERT_EQ(unrefined.trajectory.size(), 2U);
    EXPECT_LT((unrefined.trajectory[0].T_world_cam - odometryPose).norm(), 1e-9);
}

// Tracking is lost over five blank frames; relocalisation is made impossible (it would need
// more inliers than there are keypoints). The outside odometry, 2 mm off per frame, carries
// the pose across the gap: the first frame after it is found in the local map from the carried
// pose (fallback "carried_pose") and placed at the true pose. Without the odometry, or when
// the gap lasts carried_search_s or longer, or when the frame finds fewer than
// carried_min_inliers there, it stays lost.
TEST(RgbdSlam, LostFramesArePlacedFromThePoseTheOdometryCarried)
{
    const auto& seq = staticXyz();
    constexpr size_t kBlank = 40, kBack = 45;
    // The outside odometry T_cam_earlier of frame i, 2 mm off the truth.
    auto odometryAt = [&seq](size_t i)
    {
        return (seq.groundTruth[i - 1].T_world_cam - seq.groundTruth[i].T_world_cam) +
               mrpt::poses::CPose3D(0.002, 0, 0, 0, 0, 0);
    };
    // The last tracked frame's pose and the first one's after the gap.
    using Ends = std::pair<slam::TrackingResult, slam::TrackingResult>;
    auto run = [&](bool withOdometry, int searchFrames, bool blank = true,
                   int carriedMinInliers = slam::TrackerParameters{}.carried_min_inliers)
    {
        slam::TrackerParameters tp;
        tp.min_inliers_after_relocalisation = 100000;
        tp.carried_search_s = searchFrames / 30.0;  // frames at 30 frames/s
        tp.carried_min_inliers = carriedMinInliers;
        slam::RgbdSlam slam(features::OrbParameters{}, tp, deterministic());
        Ends ends;
        for (size_t i = 0; i <= kBack; ++i)
        {
            core::RgbdFrame rgbd = seq.frames[i];
            if (blank && i >= kBlank && i < kBack)
            {
                rgbd.colour = cv::Mat(rgbd.colour.size(), CV_8UC3, cv::Scalar(120, 120, 120));
                rgbd.depth = cv::Mat::zeros(rgbd.depth.size(), CV_32FC1);
            }
            auto f = slam.prepare(rgbd);
            if (withOdometry && i > 0)
            {
                f.odometry_T_cam_earlier = Eigen::Isometry3d(
                    odometryAt(i).getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen());
                f.odometryFramesBack = 1;
            }
            const auto r = slam.track(std::move(f));
            if (blank && i >= kBlank && i < kBack)
            {
                EXPECT_EQ(r.status, slam::TrackingStatus::Lost) << i;
            }
            (i + 1 == kBlank ? ends.first : ends.second) = r;
        }
        return ends;
    };
    EXPECT_EQ(run(false, 30).second.status, slam::TrackingStatus::Lost) << "no odometry";
    EXPECT_EQ(run(true, 5).second.status, slam::TrackingStatus::Lost) << "lost for too long";
    EXPECT_EQ(run(true, 0).second.status, slam::TrackingStatus::Lost) << "stage switched off";
    EXPECT_EQ(run(true, 6, true, 100000).second.status, slam::TrackingStatus::Lost)
        << "a lost frame needs carried_min_inliers, not min_inliers";
    const auto [before, back] = run(true, 6);
    ASSERT_EQ(before.status, slam::TrackingStatus::Ok);
    ASSERT_EQ(back.status, slam::TrackingStatus::Ok);
    EXPECT_EQ(back.fallback, slam::TrackingFallback::CarriedPose);
    EXPECT_EQ(slam::toString(back.fallback), "carried_pose");
    // Where tracking puts the frame when nothing is blank, and where the odometry carried it
    // (6 x 2 mm off the truth).
    const slam::TrackingResult tracked = run(true, 6, false).second;
    ASSERT_EQ(tracked.status, slam::TrackingStatus::Ok);
    EXPECT_EQ(tracked.fallback, slam::TrackingFallback::None);
    const auto toMap = [](const slam::TrackingResult& r) { return slam::toCPose3D(r.T_world_cam); };
    mrpt::poses::CPose3D carried = toMap(before);
    for (size_t i = kBlank; i <= kBack; ++i)
        carried = carried + (mrpt::poses::CPose3D() - odometryAt(i));  // + T_earlier_cam
    EXPECT_GT((carried - toMap(tracked)).norm(), 0.01) << "the check must bite";
    EXPECT_LT((toMap(back) - toMap(tracked)).norm(), 0.003) << "translation error (m)";
}

// After an outage the camera is usually back near where tracking was lost, but the thumbnail
// ranking can put an unrelated keyframe first: the keyframe tracking was lost at is tried too.
TEST(Relocalisation, TriesTheKeyFrameTrackingWasLostAtWhenThumbnailsMislead)
{
    const auto& seq = staticXyz();
    OneKeyFrameMap m;
    ASSERT_GT(m.points.size(), 200U);
    // A keyframe without map points whose thumbnail is the lost frame's own.
    const std::vector<std::shared_ptr<slam::KeyFrame>> decoy = {m.map.createKeyFrame(m.first)};
    constexpr size_t kLost = 8;
    slam::TrackerParameters params;
    params.relocalisation_candidates = 1;
    slam::Frame withoutHint = m.lostFrame(kLost, decoy);
    EXPECT_EQ(slam::relocaliseFrame(withoutHint, m.map, params), 0);

    slam::Frame withHint = m.lostFrame(kLost, decoy);
    const int inliers = slam::relocaliseFrame(withHint, m.map, params, m.keyframe.get());
    EXPECT_GE(inliers, params.min_inliers_after_relocalisation);
    const mrpt::poses::CPose3D T_first_lost =
        seq.groundTruth[kLost].T_world_cam - seq.groundTruth[0].T_world_cam;
    ASSERT_GT(T_first_lost.norm(), 0.02) << "the frames must be apart for the check to bite";
    const mrpt::poses::CPose3D error =
        slam::toCPose3D(withHint.T_cam_world.inverse()) - T_first_lost;
    EXPECT_LT(error.norm(), 0.01) << "translation error (m)";
}

// The sweep: a lost frame whose keyframe ranks last by thumbnail (five decoys look like the
// frame) is placed once the rounds reach it. One candidate and a sweep of two over the five
// keyframes after it: rounds 0 and 1 try decoys, round 2 reaches the last of the ranking;
// without the sweep no round does.
TEST(Relocalisation, SweepReachesAKeyFrameWhoseThumbnailRanksLast)
{
    OneKeyFrameMap m;
    ASSERT_GT(m.points.size(), 200U);
    constexpr size_t kLost = 8, kDecoys = 5;
    std::vector<std::shared_ptr<slam::KeyFrame>> decoys;
    for (size_t d = 0; d < kDecoys; ++d)
        decoys.push_back(m.map.createKeyFrame(m.first));  // no map points
    slam::TrackerParameters params;
    params.relocalisation_candidates = 1;
    params.relocalisation_sweep = 2;
    auto attempt = [&](const slam::TrackerParameters& p, int round)
    {
        slam::Frame f = m.lostFrame(kLost, decoys);
        return slam::relocaliseFrame(f, m.map, p, nullptr, round);
    };
    EXPECT_EQ(attempt(params, 0), 0);
    EXPECT_EQ(attempt(params, 1), 0);
    EXPECT_GE(attempt(params, 2), params.min_inliers_after_relocalisation);
    // The slices wrap around the five keyframes after the first: {3, 4} in round 4, {0, 1} in 5.
    EXPECT_GE(attempt(params, 4), params.min_inliers_after_relocalisation) << "wrapped";
    EXPECT_EQ(attempt(params, 5), 0);
    EXPECT_EQ(attempt(params, -1), 0) << "no sweep";
    slam::TrackerParameters off = params;
    off.relocalisation_sweep = 0;
    for (int round = 0; round < 6; ++round)
        EXPECT_EQ(attempt(off, round), 0) << round;
}

// A re-anchored part looks for the map only among the other parts' keyframes, and says which
// part placed the frame.
TEST(Relocalisation, AnotherPartIsSoughtAmongTheOtherPartsOnly)
{
    OneKeyFrameMap m;
    ASSERT_GT(m.points.size(), 200U);
    constexpr size_t kLost = 8;
    slam::TrackerParameters params;
    slam::Frame own = m.lostFrame(kLost, {});
    EXPECT_FALSE(slam::relocaliseInOtherPart(own, m.map, params, 0U, 0)) << "its own part";
    m.keyframe->setPart(2U);
    slam::Frame other = m.lostFrame(kLost, {});
    const auto part = slam::relocaliseInOtherPart(other, m.map, params, 0U, 0);
    ASSERT_TRUE(part.has_value());
    EXPECT_EQ(*part, 2U);
    EXPECT_GE(other.countMatches(), params.min_inliers_after_relocalisation);
}

// Merging moves a part rigidly into another's frame (culled keyframes follow their parents);
// discarding culls a part's keyframes and points.
TEST(Map, PartsMergeRigidlyAndDiscardWhole)
{
    OneKeyFrameMap m;
    slam::Map& map = m.map;
    const uint32_t part = map.newPart();
    EXPECT_EQ(part, 1U);
    EXPECT_EQ(map.liveParts(), (std::set<uint32_t>{0U, 1U}));
    m.keyframe->setPart(part);
    const Eigen::Vector3d p0 = m.points.front()->position_world;
    Eigen::Isometry3d T_to_from = Eigen::Isometry3d::Identity();
    T_to_from.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_to_from.translation() = Eigen::Vector3d(0.5, -0.2, 1.0);
    const Eigen::Isometry3d T_cam_from = m.keyframe->T_cam_world();
    map.mergePart(part, 0U, T_to_from);
    EXPECT_EQ(m.keyframe->part(), 0U);
    EXPECT_FALSE(m.keyframe->isPartOrigin());
    EXPECT_EQ(map.liveParts(), (std::set<uint32_t>{0U}));
    EXPECT_EQ(map.partsMerged(), 1U);
    EXPECT_LT((m.points.front()->position_world - T_to_from * p0).norm(), 1e-12);
    // The camera sees the point where it saw it before.
    const Eigen::Isometry3d T_cam_to = m.keyframe->T_cam_world();
    EXPECT_LT((T_cam_to * m.points.front()->position_world - T_cam_from * p0).norm(), 1e-12);
    EXPECT_GT((T_cam_to.translation() - T_cam_from.translation()).norm(), 0.5);

    const uint32_t second = map.newPart();
    m.keyframe->setPart(second);
    map.discardPart(second);
    EXPECT_TRUE(map.isDiscarded(second));
    EXPECT_TRUE(m.keyframe->isBad());
    EXPECT_TRUE(map.keyframes().empty());
    EXPECT_TRUE(map.points().empty());
    EXPECT_EQ(map.partsDiscarded(), 1U);
    EXPECT_EQ(map.partsStarted(), 2U);
}

// A map point hidden behind a mover (most keypoints around its projection have weight 0) is
// neither matched nor counted as "visible but not found": people walking in front of the
// background must not get its points culled.
TEST(ProjectionSearch, PointsBehindMoversAreNotCountedAsMissed)
{
    const auto& seq = staticXyz();
    slam::RgbdSlam slam(features::OrbParameters{}, slam::TrackerParameters{}, deterministic());
    slam::Map map;
    slam::Frame first = slam.prepare(seq.frames[0]);
    first.T_cam_world = Eigen::Isometry3d::Identity();
    auto kf = map.createKeyFrame(first);
    const auto points = addDepthPoints(map, *kf, first);
    ASSERT_GT(points.size(), 200U);
    // The same view again, with a "person" over the left half: its keypoints have weight 0.
    slam::Frame again = slam.prepare(seq.frames[0]);
    again.T_cam_world = Eigen::Isometry3d::Identity();
    std::vector<float> w(again.size(), 1.0F);
    for (size_t i = 0; i < again.size(); ++i)
        if (again.features.undistorted[i].x < 320.0F)
            w[i] = 0.0F;
    again.setWeights(w);
    const int matched = slam::searchLocalPoints(again, points, 3.0);
    int left = 0, right = 0, leftCounted = 0, rightCounted = 0;
    for (const auto& mp : points)
    {
        const double u = again.camera.project(mp->position_world).x();
        // Counted as visible: found/visible drops from 1 to 1/2 (found is only raised later,
        // by the tracker, after pose optimisation).
        const bool counted = mp->foundRatio() < 0.99;
        if (u < 300.0)
        {
            left++;
            leftCounted += counted ? 1 : 0;
        }
        else if (u > 340.0)
        {
            right++;
            rightCounted += counted ? 1 : 0;
        }
    }
    ASSERT_GT(left, 50);
    ASSERT_GT(right, 50);
    EXPECT_EQ(leftCounted, 0);
    EXPECT_EQ(rightCounted, right);
    EXPECT_GT(matched, right / 2);
    for (size_t i = 0; i < again.size(); ++i)
    {
        if (again.points[i])
        {
            EXPECT_GE(again.features.undistorted[i].x, 320.0F - 12.0F) << i;
        }
    }
}

TEST(SlamParameters, InvalidValuesNameTheKey)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("tracking", "max_depth", 0.05);
    slam::TrackerParameters t;
    EXPECT_NE(test::inputErrorOf([&] { t.loadFromConfigFile(cfg, ""); }).find("max_depth"),
              std::string::npos);
    mrpt::config::CConfigFileMemory revisit;
    revisit.write("tracking", "revisit_max_age_s", -2);
    slam::TrackerParameters r;
    EXPECT_NE(test::inputErrorOf([&] { r.loadFromConfigFile(revisit, ""); })
                  .find("revisit_max_age_s = -2"),
              std::string::npos);
    revisit.write("tracking", "revisit_max_age_s", -1);
    r.loadFromConfigFile(revisit, "");
    EXPECT_EQ(r.revisit_max_age_s, -1.0) << "-1 (follow loop closing) is valid";
    mrpt::config::CConfigFileMemory newPoints;
    newPoints.write("tracking", "keyframe_new_points", -1);
    slam::TrackerParameters n;
    EXPECT_NE(test::inputErrorOf([&] { n.loadFromConfigFile(newPoints, ""); })
                  .find("keyframe_new_points"),
              std::string::npos);
    mrpt::config::CConfigFileMemory carried;
    carried.write("tracking", "carried_search_s", -2);
    slam::TrackerParameters c;
    EXPECT_NE(test::inputErrorOf([&] { c.loadFromConfigFile(carried, ""); })
                  .find("carried_search_s = -2"),
              std::string::npos);
    for (const auto& [key, value] : {std::pair<const char*, double>{"relocalisation_sweep", -1},
                                     {"carried_min_inliers", 0},
                                     {"fallback_max_jump", -0.01},
                                     {"fallback_max_jump_deg", -1}})
    {
        mrpt::config::CConfigFileMemory bad;
        bad.write("tracking", key, value);
        slam::TrackerParameters b;
        EXPECT_NE(test::inputErrorOf([&] { b.loadFromConfigFile(bad, ""); }).find(key),
                  std::string::npos)
            << key;
    }
    mrpt::config::CConfigFileMemory cfg2;
    cfg2.write("local_mapping", "keyframe_redundancy", 1.5);
    slam::LocalMappingParameters m;
    EXPECT_NE(
        test::inputErrorOf([&] { m.loadFromConfigFile(cfg2, ""); }).find("keyframe_redundancy"),
        std::string::npos);
    for (const auto& [key, value] : {std::pair<const char*, int>{"new_point_neighbours", -1},
                                     {"ba_min_shared_observations", -3}})
    {
        mrpt::config::CConfigFileMemory bad;
        bad.write("local_mapping", key, value);
        slam::LocalMappingParameters b;
        EXPECT_NE(test::inputErrorOf([&] { b.loadFromConfigFile(bad, ""); })
                      .find(std::string(key) + " = " + std::to_string(value)),
                  std::string::npos)
            << key;
    }
}
