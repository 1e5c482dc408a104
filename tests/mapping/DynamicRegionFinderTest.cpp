// Algorithm 1 on hand-made images with known answers, and on a rendered walking sequence
// against its ground-truth dynamic mask.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "TestData.h"
#include "smap/mapping/DynamicRegionFinder.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;
using mapping::DynamicPoint;
using mapping::DynamicRegionFinder;
using mapping::DynamicRegionParameters;

namespace
{
/// 100 x 80: background 0 at 3 m, a person (15) rectangle at 2 m, a chair (9) at 2.5 m.
struct Scene
{
    cv::Mat labels = cv::Mat(80, 100, CV_8UC1, cv::Scalar(0));
    cv::Mat depth = cv::Mat(80, 100, CV_32FC1, cv::Scalar(3.0f));
    Scene()
    {
        labels(cv::Rect(10, 10, 20, 40)).setTo(15);
        depth(cv::Rect(10, 10, 20, 40)).setTo(2.0f);
        labels(cv::Rect(60, 30, 20, 20)).setTo(9);
        depth(cv::Rect(60, 30, 20, 20)).setTo(2.5f);
    }
};

/// The paper's Algorithm 1 (our growth of M and movable classes off): steps 1 and 2 exactly.
DynamicRegionParameters paper()
{
    DynamicRegionParameters p;
    p.grow_pixels = 0;
    p.movable_prior = 2.0;
    return p;
}

std::vector<DynamicPoint> pointsIn(const cv::Rect& r, int count, double depth)
{
    std::vector<DynamicPoint> pts;
    for (int i = 0; i < count; i++)
        pts.push_back(
            {r.x + 1.0 + (i * 7) % (r.width - 2), r.y + 1.0 + (i * 3) % (r.height - 2), depth});
    return pts;
}
}  // namespace

TEST(DynamicRegionFinder, ObjectWithMoreThanNumPointsGoesWhole)
{
    const Scene s;
    const DynamicRegionFinder finder(paper(), core::LabelSet::pascalVoc());
    // 21 points (> Num = 20) on the person: all its 800 pixels, nothing else.
    auto r = finder.find(s.labels, s.depth, pointsIn({10, 10, 20, 40}, 21, 2.0));
    ASSERT_EQ(r.objects.size(), 2u);  // person and chair; background is no object
    EXPECT_EQ(r.pixelsFromObjects, 800);
    EXPECT_EQ(r.pixelsNearPoints, 0);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask), 800);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask(cv::Rect(10, 10, 20, 40))), 800);

    // Exactly Num points: not the whole object, only discs of radius < 5 px at depth +- 0.1 m.
    r = finder.find(s.labels, s.depth, {{20.0, 30.0, 2.0}});
    EXPECT_EQ(r.pixelsFromObjects, 0);
    // Pixels with (du^2 + dv^2) < 25 around an integer centre: 69.
    EXPECT_EQ(r.pixelsNearPoints, 69);
    EXPECT_EQ(r.dynamicMask.at<uint8_t>(30, 24), 255);
    EXPECT_EQ(r.dynamicMask.at<uint8_t>(30, 25), 0);  // distance 5: not < sigma2
    r = finder.find(s.labels, s.depth, pointsIn({10, 10, 20, 40}, 20, 2.0));
    EXPECT_EQ(r.pixelsFromObjects, 0);
    EXPECT_GT(r.pixelsNearPoints, 0);
}

TEST(DynamicRegionFinder, APersonStandingStillIsRemovedWholeBeyondThePaper)
{
    const Scene s;
    const core::LabelSet voc = core::LabelSet::pascalVoc();
    // No dynamic point at all: the paper keeps the person, the default removes it (prior 0.9)
    // and keeps the chair (prior 0.2).
    const auto kept = DynamicRegionFinder(paper(), voc).find(s.labels, s.depth, {});
    EXPECT_EQ(cv::countNonZero(kept.dynamicMask), 0);
    DynamicRegionParameters p = paper();
    p.movable_prior = 0.5;
    const auto r = DynamicRegionFinder(p, voc).find(s.labels, s.depth, {});
    EXPECT_EQ(cv::countNonZero(r.dynamicMask), 20 * 40);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask(cv::Rect(10, 10, 20, 40))), 20 * 40);
    EXPECT_EQ(r.pixelsMovable, 20 * 40);
    // A chair counts as movable once the bar is below its prior.
    p.movable_prior = 0.2;
    EXPECT_EQ(cv::countNonZero(DynamicRegionFinder(p, voc).find(s.labels, s.depth, {}).dynamicMask),
              20 * 40 + 20 * 20);
}

TEST(DynamicRegionFinder, DepthDecidesNearObjectEdges)
{
    const Scene s;
    const DynamicRegionFinder finder(paper(), core::LabelSet::pascalVoc());
    // A point on the person's right edge (u = 29): the background (3 m) beside it stays, the
    // person pixels (2 m) within 5 px go.
    const auto r = finder.find(s.labels, s.depth, {{29.0, 30.0, 2.0}});
    for (int u = 25; u <= 33; u++)
    {
        const bool onPerson = u < 30;
        EXPECT_EQ(r.dynamicMask.at<uint8_t>(30, u) != 0, onPerson) << "u = " << u;
    }
    // A point on the background, 0.05 m from the chair's depth: within sigma1 it takes chair
    // pixels too; at 0.2 m it does not.
    auto near = finder.find(s.labels, s.depth, {{57.0, 40.0, 2.45}});
    EXPECT_EQ(near.dynamicMask.at<uint8_t>(40, 60), 255);
    EXPECT_EQ(near.dynamicMask.at<uint8_t>(40, 56), 0);  // background at 3 m
    auto far = finder.find(s.labels, s.depth, {{57.0, 40.0, 2.7}});
    EXPECT_EQ(cv::countNonZero(far.dynamicMask), 0);
    // Unknown depth: taken from the depth image at the point.
    auto fromImage = finder.find(s.labels, s.depth, {{20.0, 30.0, 0.0}});
    EXPECT_EQ(fromImage.pixelsNearPoints, 69);
}

TEST(DynamicRegionFinder, NonObjectClassesAndParameters)
{
    Scene s;
    // With background counted as an object, 21 points on it remove the whole background.
    DynamicRegionParameters p = paper();
    p.non_object_classes = "";
    const DynamicRegionFinder all(p, core::LabelSet::pascalVoc());
    const auto r = all.find(s.labels, s.depth, pointsIn({35, 5, 20, 70}, 21, 3.0));
    EXPECT_EQ(r.pixelsFromObjects, 100 * 80 - 800 - 400);
    p.non_object_classes = "nosuchclass";
    EXPECT_NE(test::inputErrorOf([&] { DynamicRegionFinder f(p, core::LabelSet::pascalVoc()); })
                  .find("nosuchclass"),
              std::string::npos);
}

TEST(DynamicRegionFinder, GrowthFollowsDepthAndStopsAtItsSteps)
{
    const Scene s;
    DynamicRegionParameters p = paper();
    const std::vector<DynamicPoint> centre = {{20.0, 30.0, 2.0}};  // 69-pixel disc on the person
    const cv::Mat disc = DynamicRegionFinder(p, core::LabelSet::pascalVoc())
                             .find(s.labels, s.depth, centre)
                             .dynamicMask;
    ASSERT_EQ(cv::countNonZero(disc), 69);

    // Three 4-neighbour steps: the disc dilated three times by a cross, inside the person
    // (2 m; the background at 3 m is beyond depth_tolerance), computed independently.
    p.grow_pixels = 3;
    auto r = DynamicRegionFinder(p, core::LabelSet::pascalVoc()).find(s.labels, s.depth, centre);
    cv::Mat expected;
    cv::dilate(disc, expected, cv::getStructuringElement(cv::MORPH_CROSS, {3, 3}), {-1, -1}, 3);
    cv::Mat person(disc.size(), CV_8UC1, cv::Scalar(0));
    person(cv::Rect(10, 10, 20, 40)).setTo(255);
    expected &= person;
    EXPECT_EQ(cv::countNonZero(r.dynamicMask != expected), 0);
    EXPECT_EQ(r.pixelsNearPoints, 69);
    EXPECT_EQ(r.pixelsGrown, cv::countNonZero(expected) - 69);

    // Enough steps: the whole person and nothing else (background 1 m behind, chair apart).
    p.grow_pixels = 100;
    r = DynamicRegionFinder(p, core::LabelSet::pascalVoc()).find(s.labels, s.depth, centre);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask), 800);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask(cv::Rect(10, 10, 20, 40))), 800);

    // A slope (5 mm per pixel, a floor seen at a glance) is followed; a 0.15 m step is not,
    // and a pixel without depth neither joins nor passes the growth on.
    cv::Mat slope(20, 60, CV_32FC1);
    for (int u = 0; u < 60; ++u)
        slope.col(u).setTo(2.0f + 0.005f * static_cast<float>(u) + (u >= 40 ? 0.15f : 0.0f));
    slope(cv::Rect(0, 15, 60, 1)).setTo(0.0f);
    const cv::Mat background(20, 60, CV_8UC1, cv::Scalar(0));
    p.grow_pixels = 60;
    r = DynamicRegionFinder(p, core::LabelSet::pascalVoc())
            .find(background, slope, {{5.0, 5.0, 2.025}});
    EXPECT_EQ(cv::countNonZero(r.dynamicMask(cv::Rect(0, 0, 40, 15))), 40 * 15);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask(cv::Rect(40, 0, 20, 20))), 0);
    EXPECT_EQ(cv::countNonZero(r.dynamicMask(cv::Rect(0, 15, 60, 5))), 0);
}

TEST(DynamicRegionFinder, RemovesTheWalkersOfARenderedFrame)
{
    sim::GeneratorOptions o;
    o.preset = "walking_xyz";
    o.noiseFreeDepth = true;
    sim::SequenceGenerator gen(o);
    const auto f = gen.frame(60);
    const cv::Mat& truth = f.rendered.dynamic;
    ASSERT_GT(cv::countNonZero(truth), 5000) << "no walker in view";
    // A perfect dynamic filter: keypoints on a 12 px grid, dynamic where the truth says so.
    std::vector<DynamicPoint> points;
    for (int v = 6; v < truth.rows; v += 12)
        for (int u = 6; u < truth.cols; u += 12)
            if (truth.at<uint8_t>(v, u) && f.depthNoiseFree.at<float>(v, u) > 0.0f)
                points.push_back({double(u), double(v), f.depthNoiseFree.at<float>(v, u)});
    const DynamicRegionFinder finder(DynamicRegionParameters(), core::LabelSet::pascalVoc());
    const auto r = finder.find(f.rendered.labels, f.depthNoiseFree, points);
    const cv::Mat valid = f.depthNoiseFree > 0.0f;
    const double truthPixels = cv::countNonZero(truth & valid);
    const double removedTruth = cv::countNonZero(truth & valid & r.dynamicMask);
    const double staticPixels = cv::countNonZero(~truth & valid);
    const double removedStatic = cv::countNonZero(~truth & valid & r.dynamicMask);
    EXPECT_GT(removedTruth / truthPixels, 0.99);
    EXPECT_LT(removedStatic / staticPixels, 0.01);
    EXPECT_GT(r.pixelsFromObjects, 0);  // walkers carry more than 20 points: removed whole
}
