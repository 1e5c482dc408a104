// The dynamic feature filter on rendered frames with exact ground truth: ego-motion against
// the true relative pose, no dynamic points in a static scene, people's points found.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "TestData.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/dynamic/FrameWarp.h"
#include "smap/features/OrbExtractor.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;

namespace
{
Eigen::Isometry3d toEigen(const mrpt::poses::CPose3D& p)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const auto M = p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            T.matrix()(r, c) = M(r, c);
    return T;
}

/// Rotation angle (rad) between two poses' rotations.
double rotationError(const Eigen::Isometry3d& T, const Eigen::Isometry3d& truth)
{
    return Eigen::AngleAxisd(T.linear().transpose() * truth.linear()).angle();
}

/// Distance (m) between two poses' translations.
double translationError(const Eigen::Isometry3d& T, const Eigen::Isometry3d& truth)
{
    return (T.translation() - truth.translation()).norm();
}

struct Prepared
{
    sim::SyntheticFrame frame;
    features::FeatureSet features;
};

Prepared prepare(sim::SequenceGenerator& gen, const features::OrbExtractor& orb, size_t i)
{
    Prepared p{gen.frame(i), {}};
    p.features = orb.extract(p.frame.rendered.colour);
    features::undistortKeypoints(p.features, gen.options().camera);
    features::assignDepth(p.features, p.frame.rendered.depth, 40.0, 0.1, 8.0, 1e9);
    return p;
}

struct Scores
{
    int tp = 0, fp = 0, fn = 0, tn = 0;
    double recall() const { return tp + fn > 0 ? static_cast<double>(tp) / (tp + fn) : 1.0; }
    double precision() const { return tp + fp > 0 ? static_cast<double>(tp) / (tp + fp) : 1.0; }
};

// Runs the filter over frames [first, first + n) and scores its decisions against the
// ground-truth dynamic masks at the keypoints.
Scores runFilter(const std::string& preset, dynamic::FilterMode mode, size_t first, size_t n)
{
    sim::GeneratorOptions o;
    o.preset = preset;
    sim::SequenceGenerator gen(o);
    const features::OrbExtractor orb{features::OrbParameters{}};
    dynamic::DynamicParameters dp;
    dp.mode = mode;
    dynamic::DynamicFilter filter(dp);
    Scores s;
    for (size_t i = first; i < first + n; ++i)
    {
        const Prepared p = prepare(gen, orb, i);
        const auto r =
            filter.process(p.frame.rendered.colour, p.frame.rendered.depth, p.features, o.camera);
        if (i == first)
            continue;
        EXPECT_TRUE(r.egoMotion.valid) << i;
        for (size_t k = 0; k < p.features.size(); ++k)
        {
            const auto& pt = p.features.keypoints[k].pt;
            const bool truth =
                p.frame.rendered.dynamic.at<uint8_t>(static_cast<int>(std::lround(pt.y)),
                                                     static_cast<int>(std::lround(pt.x))) != 0;
            const bool said = r.keypoints[k].dynamic;
            (truth ? (said ? s.tp : s.fn) : (said ? s.fp : s.tn))++;
        }
    }
    return s;
}
}  // namespace

TEST(EgoMotion, FivePointWithDepthScaleMatchesTheTrueRelativePose)
{
    sim::GeneratorOptions o;
    o.preset = "static_xyz";
    sim::SequenceGenerator gen(o);
    const features::OrbExtractor orb{features::OrbParameters{}};
    dynamic::DynamicParameters dp;
    // Frames 25 apart (about 20 cm). The five-point solution is only loosely conditioned on
    // this scene (small field of view, rotation and sideways translation look alike), so the
    // check is on the conventions and the metric scale: direction, length and rotation.
    const Prepared a = prepare(gen, orb, 20), b = prepare(gen, orb, 45);
    const auto ego = dynamic::estimateEgoMotionFivePoint(a.features, b.features, o.camera, dp);
    ASSERT_TRUE(ego.valid) << ego.matches << " matches, " << ego.inliers << " inliers, "
                           << ego.scaleSamples << " scale samples";
    const Eigen::Isometry3d truth =
        toEigen(b.frame.T_world_cam).inverse() * toEigen(a.frame.T_world_cam);
    const Eigen::Vector3d te = ego.T_cur_prev.translation(), tt = truth.translation();
    ASSERT_GT(tt.norm(), 0.1);
    std::printf(
        "five-point: |t| %.4f m (true %.4f), direction error %.2f deg, rotation error %.3f deg\n",
        te.norm(), tt.norm(), std::acos(te.normalized().dot(tt.normalized())) * 180 / M_PI,
        rotationError(ego.T_cur_prev, truth) * 180 / M_PI);
    EXPECT_NEAR(te.norm(), tt.norm(), 0.2 * tt.norm());
    EXPECT_GT(te.normalized().dot(tt.normalized()), std::cos(20.0 * M_PI / 180.0));
    EXPECT_LT(rotationError(ego.T_cur_prev, truth), 1.5 * M_PI / 180.0);
    EXPECT_GT(ego.inliers, 100);
}

// Depth-aided PnP between nearby frames (the strong mode's ego-motion): metric and accurate
// where the five-point method is poorly conditioned.
TEST(EgoMotion, DepthPnpMatchesTheTrueRelativePoseOverAShortBaseline)
{
    sim::GeneratorOptions o;
    o.preset = "static_xyz";
    sim::SequenceGenerator gen(o);
    const features::OrbExtractor orb{features::OrbParameters{}};
    dynamic::DynamicParameters dp;
    dp.ego_max_queries = 0;  // every match; the filter's subsampled estimate is tested below
    for (size_t first : {20U, 60U, 100U})
    {
        const Prepared a = prepare(gen, orb, first), b = prepare(gen, orb, first + 2);
        const auto ego = dynamic::estimateEgoMotionDepthPnp(a.features, b.features, o.camera, dp);
        ASSERT_TRUE(ego.valid) << first;
        const Eigen::Isometry3d truth =
            toEigen(b.frame.T_world_cam).inverse() * toEigen(a.frame.T_world_cam);
        EXPECT_LT(translationError(ego.T_cur_prev, truth), 0.005) << first;
        EXPECT_LT(rotationError(ego.T_cur_prev, truth), 0.15 * M_PI / 180.0) << first;
        EXPECT_GT(ego.inliers, 100);
    }
}

TEST(DynamicFilter, StrongModeEgoMotionIsRefinedOnTheFlowTracks)
{
    // Default parameters: descriptor matches of 250 keypoints give the first estimate, the
    // Lucas-Kanade tracks of the static keypoints refine it.
    sim::GeneratorOptions o;
    o.preset = "walking_xyz";
    sim::SequenceGenerator gen(o);
    const features::OrbExtractor orb{features::OrbParameters{}};
    dynamic::DynamicFilter filter{dynamic::DynamicParameters{}};
    for (size_t first : {20U, 60U, 100U})
    {
        const Prepared a = prepare(gen, orb, first), b = prepare(gen, orb, first + 2);
        filter.reset();
        filter.process(a.frame.rendered.colour, a.frame.rendered.depth, a.features, o.camera);
        const auto r =
            filter.process(b.frame.rendered.colour, b.frame.rendered.depth, b.features, o.camera);
        ASSERT_TRUE(r.egoMotion.valid) << first;
        const Eigen::Isometry3d truth =
            toEigen(b.frame.T_world_cam).inverse() * toEigen(a.frame.T_world_cam);
        EXPECT_LT(translationError(r.egoMotion.T_cur_prev, truth), 0.003) << first;
        EXPECT_LT(rotationError(r.egoMotion.T_cur_prev, truth), 0.1 * M_PI / 180.0) << first;
    }
}

TEST(FrameWarp, WarpWithTheTruePoseReproducesTheCurrentFrame)
{
    sim::GeneratorOptions o;
    o.preset = "static_xyz";
    o.noiseFreeDepth = true;
    sim::SequenceGenerator gen(o);
    const auto a = gen.frame(10), b = gen.frame(14);
    cv::Mat ga, gb;
    cv::cvtColor(a.rendered.colour, ga, cv::COLOR_BGR2GRAY);
    cv::cvtColor(b.rendered.colour, gb, cv::COLOR_BGR2GRAY);
    const Eigen::Isometry3d T = toEigen(b.T_world_cam).inverse() * toEigen(a.T_world_cam);
    const auto w = dynamic::warpIntoCurrentView(ga, a.rendered.depth, o.camera, T);
    // Where the warp landed, the warped image and depth agree with the current frame.
    cv::Mat diff;
    cv::absdiff(w.grey, gb, diff);
    const cv::Mat landed = w.valid != 0;
    const double meanDiff = cv::mean(diff, landed)[0];
    const double meanDiffUnwarped = cv::mean(
        [&]
        {
            cv::Mat d;
            cv::absdiff(ga, gb, d);
            return d;
        }(),
        landed)[0];
    EXPECT_LT(meanDiff, 6.0);
    EXPECT_LT(meanDiff, 0.5 * meanDiffUnwarped);
    EXPECT_GT(cv::countNonZero(landed), 0.8 * ga.total());
    cv::Mat zdiff;
    cv::absdiff(w.depth, b.rendered.depth, zdiff);
    EXPECT_LT(cv::mean(zdiff, landed)[0], 0.02);
}

TEST(DynamicFilter, StaticSceneHasAlmostNoDynamicKeypoints)
{
    const Scores s = runFilter("static_xyz", dynamic::FilterMode::Paper, 30, 6);
    EXPECT_EQ(s.tp + s.fn, 0) << "no ground-truth movers in a static preset";
    EXPECT_LT(s.fp, 0.02 * (s.fp + s.tn)) << s.fp << " false positives of " << s.fp + s.tn;
}

TEST(DynamicFilter, PaperModeFindsWalkingPeople)
{
    const Scores s = runFilter("walking_xyz", dynamic::FilterMode::Paper, 40, 8);
    ASSERT_GT(s.tp + s.fn, 50) << "people must be in view";
    RecordProperty("recall", std::to_string(s.recall()));
    RecordProperty("precision", std::to_string(s.precision()));
    std::printf(
        "paper mode on walking_xyz frames 40-47: recall %.3f precision %.3f (tp %d fp %d fn %d)\n",
        s.recall(), s.precision(), s.tp, s.fp, s.fn);
    EXPECT_GT(s.recall(), 0.5);
    EXPECT_GT(s.precision(), 0.8);
}

TEST(DynamicFilter, StrongModeFindsMoreOfThePeopleAndNoMoreStaticPoints)
{
    const Scores paper = runFilter("walking_xyz", dynamic::FilterMode::Paper, 40, 8);
    const Scores strong = runFilter("walking_xyz", dynamic::FilterMode::Strong, 40, 8);
    std::printf(
        "walking_xyz frames 40-47: paper recall %.3f precision %.3f, strong recall %.3f "
        "precision %.3f\n",
        paper.recall(), paper.precision(), strong.recall(), strong.precision());
    EXPECT_GT(strong.recall(), paper.recall());
    EXPECT_GT(strong.recall(), 0.8);
    EXPECT_GT(strong.precision(), 0.8);
    const Scores still = runFilter("static_xyz", dynamic::FilterMode::Strong, 30, 6);
    EXPECT_LT(still.fp, 0.02 * (still.fp + still.tn)) << still.fp << " false positives";
}

TEST(DynamicFilter, ModeOffAndFirstFrameMarkNothing)
{
    sim::GeneratorOptions o;
    o.preset = "walking_xyz";
    sim::SequenceGenerator gen(o);
    const features::OrbExtractor orb{features::OrbParameters{}};
    dynamic::DynamicParameters dp;
    dp.mode = dynamic::FilterMode::Paper;
    dynamic::DynamicFilter paper(dp);
    dp.mode = dynamic::FilterMode::Off;
    dynamic::DynamicFilter off(dp);
    for (size_t i = 40; i < 42; ++i)
    {
        const Prepared p = prepare(gen, orb, i);
        const auto rp =
            paper.process(p.frame.rendered.colour, p.frame.rendered.depth, p.features, o.camera);
        const auto ro =
            off.process(p.frame.rendered.colour, p.frame.rendered.depth, p.features, o.camera);
        EXPECT_EQ(ro.numDynamic(), 0U);
        EXPECT_EQ(ro.weights(), std::vector<float>(p.features.size(), 1.0F));
        EXPECT_TRUE(ro.evaluated);
        if (i == 40)
        {
            EXPECT_EQ(rp.numDynamic(), 0U) << "no previous frame yet";
            EXPECT_FALSE(rp.evaluated);
            EXPECT_EQ(rp.weights(), std::vector<float>(p.features.size(), 0.0F))
                << "no evidence yet: nothing may start the map";
        }
        else
        {
            EXPECT_TRUE(rp.evaluated);
            EXPECT_GT(rp.numDynamic(), 0U);
        }
    }
}

TEST(DynamicParameters, InvalidValuesNameTheKey)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("dynamic", "mode", "fancy");
    dynamic::DynamicParameters p;
    EXPECT_NE(test::inputErrorOf([&] { p.loadFromConfigFile(cfg, ""); }).find("fancy"),
              std::string::npos);
    mrpt::config::CConfigFileMemory cfg2;
    cfg2.write("dynamic", "lk_window", 20);
    dynamic::DynamicParameters p2;
    EXPECT_NE(test::inputErrorOf([&] { p2.loadFromConfigFile(cfg2, ""); }).find("lk_window"),
              std::string::npos);
}
