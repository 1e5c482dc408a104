// Bundle adjustment on a synthetic map with exact observations: drifted keyframes and perturbed
// points return to the truth, the first keyframe holds the world frame, a wrong observation is
// removed rather than followed, and a keyframe tied to the others by a few points that moved
// holds its pose.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <random>

#include "smap/slam/BundleAdjustment.h"
#include "smap/slam/Map.h"

using namespace smap;

namespace
{
constexpr int kKeyFrames = 8;
constexpr int kPoints = 250;
const int kMinShared = slam::LocalMappingParameters{}.ba_min_shared_observations;

core::PinholeCamera testCamera()
{
    core::PinholeCamera c;
    c.width = 640;
    c.height = 480;
    c.fx = c.fy = 525;
    c.cx = 319.5;
    c.cy = 239.5;
    return c;
}

Eigen::Isometry3d truePose(int k)  // T_cam_world of keyframe k: a sideways pass, turning
{
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.linear() =
        Eigen::AngleAxisd(-0.03 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_world_cam.translation() = Eigen::Vector3d(0.1 * k, 0.01 * k, 0.02 * k);
    return T_world_cam.inverse();
}

struct Scene
{
    slam::Map map;
    std::vector<std::shared_ptr<slam::KeyFrame>> keyframes;
    std::vector<Eigen::Vector3d> truth;  // point positions, world
    std::vector<std::shared_ptr<slam::MapPoint>> points;
};

// Every point seen by every keyframe it projects into, at its exact pixel and depth.
void build(Scene& s)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-1.5, 2.2), uy(-1.0, 1.0), uz(2.0, 5.0);
    const core::PinholeCamera camera = testCamera();
    const double bf = 0.08 * camera.fx;
    for (int i = 0; i < kPoints; ++i)
        s.truth.emplace_back(ux(rng), uy(rng), uz(rng));
    std::vector<std::vector<std::pair<int, size_t>>> seenBy(kPoints);
    for (int k = 0; k < kKeyFrames; ++k)
    {
        slam::Frame f;
        f.camera = camera;
        f.bf = bf;
        f.closeDepth = 3.0;
        f.features.pyramid = features::ScalePyramid::make(8, 1.2);
        for (int i = 0; i < kPoints; ++i)
        {
            const Eigen::Vector3d p_cam = truePose(k) * s.truth[static_cast<size_t>(i)];
            const Eigen::Vector2d uv = camera.project(p_cam);
            if (p_cam.z() <= 0 || uv.x() < 0 || uv.y() < 0 || uv.x() >= 640 || uv.y() >= 480)
                continue;
            cv::KeyPoint kp(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31);
            kp.octave = i % 2;
            seenBy[static_cast<size_t>(i)].emplace_back(k, f.features.keypoints.size());
            f.features.keypoints.push_back(kp);
            f.features.undistorted.push_back(kp.pt);
            f.features.depth.push_back(static_cast<float>(p_cam.z()));
            f.features.rightU.push_back(static_cast<float>(uv.x() - bf / p_cam.z()));
        }
        f.features.descriptors =
            cv::Mat::zeros(static_cast<int>(f.features.keypoints.size()), 32, CV_8UC1);
        f.weights.assign(f.features.keypoints.size(), 1.0F);
        f.clearMatches();
        f.T_cam_world = truePose(k);
        s.keyframes.push_back(s.map.createKeyFrame(f));
    }
    for (int i = 0; i < kPoints; ++i)
    {
        const auto& seen = seenBy[static_cast<size_t>(i)];
        if (seen.size() < 2)
        {
            s.points.push_back(nullptr);
            continue;
        }
        auto p = s.map.createPoint(s.truth[static_cast<size_t>(i)],
                                   s.keyframes[static_cast<size_t>(seen[0].first)].get());
        for (const auto& [k, index] : seen)
        {
            auto& kf = s.keyframes[static_cast<size_t>(k)];
            p->addObservation(kf.get(), index);
            kf->points[index] = p;
        }
        s.points.push_back(p);
    }
    for (auto& kf : s.keyframes)
        kf->updateConnections(15);
}

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    return (a.inverse().translation() - b.inverse().translation()).norm();
}

double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle() * 180.0 / M_PI;
}
}  // namespace

TEST(GlobalBundleAdjustment, DriftedKeyFramesAndPointsReturnToTheTruth)
{
    Scene s;
    build(s);
    // Drift growing along the pass (as tracking leaves it), noise on the points.
    for (int k = 1; k < kKeyFrames; ++k)
    {
        Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
        drift.linear() = Eigen::AngleAxisd(0.004 * k, Eigen::Vector3d(0.2, 1.0, 0.3).normalized())
                             .toRotationMatrix();
        drift.translation() = Eigen::Vector3d(0.008, -0.004, 0.006) * k;
        s.keyframes[static_cast<size_t>(k)]->setPose(drift * truePose(k));
    }
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.02);
    int nPoints = 0;
    for (auto& p : s.points)
    {
        if (!p)
            continue;
        p->position_world += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
        nPoints++;
    }
    const auto& last = s.keyframes.back();
    ASSERT_GT(translationError(last->T_cam_world(), truePose(kKeyFrames - 1)), 0.05);

    const std::atomic<bool> never{false};
    const uint64_t correctionsBefore = s.map.corrections();
    const auto stats = slam::globalBundleAdjustment(s.map, 10, kMinShared, never);
    EXPECT_EQ(s.map.corrections(), correctionsBefore + 1) << "tracking is told to follow";
    EXPECT_EQ(stats.keyframes, kKeyFrames - 1);
    EXPECT_EQ(stats.fixedKeyframes, 1);
    EXPECT_EQ(stats.points, nPoints);
    EXPECT_EQ(stats.outliersRemoved, 0);
    EXPECT_TRUE(s.keyframes[0]->T_cam_world().isApprox(truePose(0), 1e-12))
        << "the first keyframe holds the world frame";
    for (int k = 1; k < kKeyFrames; ++k)
    {
        const auto& kf = s.keyframes[static_cast<size_t>(k)];
        EXPECT_LT(translationError(kf->T_cam_world(), truePose(k)), 1e-4) << "keyframe " << k;
        EXPECT_LT(rotationErrorDeg(kf->T_cam_world(), truePose(k)), 1e-3) << "keyframe " << k;
    }
    for (size_t i = 0; i < s.points.size(); ++i)
    {
        if (!s.points[i])
            continue;
        EXPECT_LT((s.points[i]->position_world - s.truth[i]).norm(), 1e-4) << "point " << i;
    }
}

TEST(GlobalBundleAdjustment, AWrongObservationIsRemovedNotFollowed)
{
    Scene s;
    build(s);
    // Keyframe 3 sees one point 40 px away from where it is.
    auto& kf = *s.keyframes[3];
    size_t bad = 0;
    while (!kf.points[bad])
        ++bad;
    const auto wrongPoint = kf.points[bad];
    kf.features.undistorted[bad].x += 40.0F;
    kf.features.rightU[bad] += 40.0F;
    Eigen::Isometry3d nudged = truePose(3);
    nudged.translation() += Eigen::Vector3d(0.01, 0, 0);
    kf.setPose(nudged);

    const std::atomic<bool> never{false};
    const auto stats = slam::globalBundleAdjustment(s.map, 10, kMinShared, never);
    EXPECT_EQ(stats.outliersRemoved, 1);
    EXPECT_FALSE(kf.points[bad]) << "the observation is gone from the keyframe";
    EXPECT_FALSE(wrongPoint->isObservedBy(&kf));
    for (int k = 1; k < kKeyFrames; ++k)
        EXPECT_LT(translationError(s.keyframes[static_cast<size_t>(k)]->T_cam_world(), truePose(k)),
                  1e-4)
            << "keyframe " << k;
}

TEST(GlobalBundleAdjustment, AnEmptyMapIsLeftAlone)
{
    slam::Map map;
    const std::atomic<bool> never{false};
    const auto stats = slam::globalBundleAdjustment(map, 10, kMinShared, never);
    EXPECT_EQ(stats.keyframes, 0);
    EXPECT_EQ(stats.points, 0);
}

namespace
{
// The last keyframe keeps `kept` of its points, and sees the first `moved` of them where they
// would be had they moved by `shift` (people that walked): those agree with a pose `shift` away.
const slam::KeyFrame& tieLastKeyFrameByMovedPoints(Scene& s, int kept, int moved,
                                                   const Eigen::Vector3d& shift)
{
    slam::KeyFrame& kf = *s.keyframes.back();
    const core::PinholeCamera camera = testCamera();
    int shared = 0;
    for (size_t i = 0; i < kf.points.size(); ++i)
    {
        const auto mp = kf.points[i];
        if (!mp)
            continue;
        if (shared++ >= kept)
        {
            mp->eraseObservation(&kf);
            kf.points[i].reset();
            continue;
        }
        if (shared > moved)
            continue;
        const Eigen::Vector3d p_cam = truePose(kKeyFrames - 1) * (mp->position_world + shift);
        const Eigen::Vector2d uv = camera.project(p_cam);
        kf.features.undistorted[i] =
            cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
        kf.features.rightU[i] = static_cast<float>(uv.x() - kf.bf / p_cam.z());
    }
    return kf;
}

// The last keyframe tied by `kept` points, `moved` of which walked 25 cm, then one global or
// local adjustment: its stats and how far the keyframe ends from the truth.
struct TiedRun
{
    slam::BundleAdjustmentStats stats;
    double error = 0.0;
    double otherKeyFramesError = 0.0;  // the largest, keyframes 1 .. n-2
};

TiedRun adjustTiedKeyFrame(int minShared, bool global, int kept = 8, int moved = 8)
{
    Scene s;
    build(s);
    const auto& kf = tieLastKeyFrameByMovedPoints(s, kept, moved, Eigen::Vector3d(0.25, 0.0, 0.05));
    const std::atomic<bool> never{false};
    slam::LocalMappingParameters params;
    params.ba_min_shared_observations = minShared;
    TiedRun r;
    r.stats = global ? slam::globalBundleAdjustment(s.map, 10, minShared, never)
                     : slam::localBundleAdjustment(s.keyframes.back(), s.map, params, never);
    r.error = translationError(kf.T_cam_world(), truePose(kKeyFrames - 1));
    for (int k = 1; k + 1 < kKeyFrames; ++k)
        r.otherKeyFramesError = std::max(
            r.otherKeyFramesError,
            translationError(s.keyframes[static_cast<size_t>(k)]->T_cam_world(), truePose(k)));
    return r;
}
}  // namespace

TEST(GlobalBundleAdjustment, AKeyFrameTiedByAFewMovedPointsHoldsItsPose)
{
    const TiedRun held = adjustTiedKeyFrame(kMinShared, true);
    EXPECT_EQ(held.stats.weaklyTiedHeld, 1);
    EXPECT_EQ(held.stats.fixedKeyframes, 2) << "the world frame and the weakly tied one";
    EXPECT_LT(held.error, 1e-9) << "it keeps the pose tracking gave it";
    EXPECT_EQ(held.stats.outliersRemoved, 8) << "the moved points are not followed";
    EXPECT_LT(held.otherKeyFramesError, 1e-4);

    const TiedRun free = adjustTiedKeyFrame(0, true);
    EXPECT_EQ(free.stats.weaklyTiedHeld, 0);
    EXPECT_GT(free.error, 0.15) << "without the rule the few points carry it off";
    EXPECT_LT(free.otherKeyFramesError, 1e-4);
}

TEST(LocalBundleAdjustment, AKeyFrameTiedByAFewMovedPointsHoldsItsPose)
{
    const TiedRun held = adjustTiedKeyFrame(kMinShared, false);
    EXPECT_EQ(held.stats.weaklyTiedHeld, 1);
    EXPECT_LT(held.error, 1e-9);
    const TiedRun free = adjustTiedKeyFrame(0, false);
    EXPECT_EQ(free.stats.weaklyTiedHeld, 0);
    EXPECT_GT(free.error, 0.15);
}

TEST(GlobalBundleAdjustment, AKeyFrameLeftWeaklyTiedByItsOutliersReturnsToItsPose)
{
    // 24 shared points, enough to take part, but 14 of them walked: the robust pass follows
    // them and finds the other 10 outliers, which leaves 14 inliers.
    const TiedRun held = adjustTiedKeyFrame(kMinShared, true, 24, 14);
    EXPECT_EQ(held.stats.weaklyTiedHeld, 1);
    EXPECT_LT(held.error, 1e-9) << "back where tracking put it, and held";
    EXPECT_LT(held.otherKeyFramesError, 1e-4);
    const TiedRun free = adjustTiedKeyFrame(0, true, 24, 14);
    EXPECT_GT(free.error, 0.15) << "without the rule the walked points carry it off";
}
