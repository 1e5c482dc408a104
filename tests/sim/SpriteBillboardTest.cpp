// Billboards checked against geometry: where a sprite lands in the image, at what depth, and
// that what is drawn is the surface surfacePoint() describes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "TestData.h"
#include "smap/sim/SpriteBillboard.h"

using namespace smap;

namespace
{
/// An opaque 40 x 100 rectangle (a "person" 2.5 times as tall as wide) on a transparent margin
/// of 10 px: 60 x 120 texels.
cv::Mat rectangleSprite()
{
    cv::Mat s(120, 60, CV_8UC4, cv::Scalar(0, 0, 0, 0));
    s(cv::Rect(10, 10, 40, 100)).setTo(cv::Scalar(30, 120, 210, 255));
    return s;
}

/// Camera at the origin looking along world +y: optical x = world x, y = world -z, z = world y.
mrpt::poses::CPose3D lookingAlongY()
{
    mrpt::math::CMatrixDouble33 R;
    R.setZero();
    R(0, 0) = 1.0;   // optical x -> world x
    R(2, 1) = -1.0;  // optical y -> world -z
    R(1, 2) = 1.0;   // optical z -> world y
    return mrpt::poses::CPose3D(R, mrpt::math::CVectorFixedDouble<3>());
}

sim::BillboardLayers emptyLayers(const core::PinholeCamera& cam)
{
    const cv::Size size(cam.width, cam.height);
    return {cv::Mat(size, CV_8UC3, cv::Scalar(0, 0, 0)), cv::Mat::zeros(size, CV_32FC1),
            cv::Mat::zeros(size, CV_8UC1), cv::Mat::zeros(size, CV_16UC1),
            cv::Mat::zeros(size, CV_8UC1)};
}

/// A billboard 3 m ahead of the camera, feet 1.2 m below it, facing the camera.
sim::BillboardPose poseAhead()
{
    sim::BillboardPose p;
    p.feet = {0.0, 3.0, -1.2};
    p.normal = {0.0, -1.0, 0.0};
    p.height = 1.8;
    return p;
}
}  // namespace

TEST(SpriteBillboard, FlatSpriteLandsWhereThePinholeModelPutsIt)
{
    const auto cam = test::centredCamera(320, 240, 250.0);
    const sim::SpriteBillboard b(rectangleSprite(), {});
    auto layers = emptyLayers(cam);
    const auto pose = poseAhead();
    b.draw(pose, nullptr, cam, lookingAlongY(), 15, 7, layers);

    // The opaque rectangle spans a in [10/60, 50/60), b in [10/120, 110/120) of a 0.9 x 1.8 m
    // sprite: x in [-0.3, 0.3) m, height [0.15, 1.65) m, i.e. z in [-1.05, 0.45) m, at 3 m.
    const double f = 250.0;
    const double u0 = cam.cx + f * -0.3 / 3.0, u1 = cam.cx + f * 0.3 / 3.0;
    const double v0 = cam.cy - f * 0.45 / 3.0, v1 = cam.cy + f * 1.05 / 3.0;
    const double expected = (u1 - u0) * (v1 - v0);
    const int drawn = cv::countNonZero(layers.instances);
    EXPECT_NEAR(drawn, expected, 0.03 * expected);
    for (int v = 0; v < cam.height; v++)
    {
        for (int u = 0; u < cam.width; u++)
        {
            const bool in = layers.instances.at<uint16_t>(v, u) != 0;
            if (!in)
                continue;
            EXPECT_GE(u, u0 - 1);
            EXPECT_LE(u, u1 + 1);
            EXPECT_GE(v, v0 - 1);
            EXPECT_LE(v, v1 + 1);
            ASSERT_FLOAT_EQ(layers.depth.at<float>(v, u), 3.0f);  // the plane faces the camera
            ASSERT_EQ(layers.labels.at<uint8_t>(v, u), 15);
            ASSERT_EQ(layers.instances.at<uint16_t>(v, u), 7);
            ASSERT_EQ(layers.dynamic.at<uint8_t>(v, u), 255);  // no `before`: always moving
            ASSERT_EQ(layers.colour.at<cv::Vec3b>(v, u), cv::Vec3b(30, 120, 210));
        }
    }
}

TEST(SpriteBillboard, NearerSurfacesHideItAndHolesDoNot)
{
    const auto cam = test::centredCamera(320, 240, 250.0);
    const sim::SpriteBillboard b(rectangleSprite(), {});
    auto layers = emptyLayers(cam);
    layers.depth.colRange(0, 160).setTo(2.0f);    // a wall in front on the left half
    layers.depth.colRange(160, 320).setTo(5.0f);  // behind on the right half
    layers.depth.at<float>(120, 150) = 0.0f;      // a hole in front: the person shows
    b.draw(poseAhead(), nullptr, cam, lookingAlongY(), 15, 7, layers);
    EXPECT_EQ(cv::countNonZero(layers.instances.colRange(0, 160)), 1);
    EXPECT_EQ(layers.instances.at<uint16_t>(120, 150), 7);
    EXPECT_GT(cv::countNonZero(layers.instances.colRange(160, 320)), 500);
    EXPECT_EQ(layers.depth.at<float>(120, 100), 2.0f);  // the wall stays
}

TEST(SpriteBillboard, DrawnPixelsLieOnTheSurfaceWithReliefAndLean)
{
    const auto cam = test::centredCamera(320, 240, 250.0);
    const sim::SpriteBillboard b(rectangleSprite(), {0.12, true});
    auto pose = poseAhead();
    pose.pivotHeight = 0.5;
    pose.leanTowards = 0.1;
    pose.leanAcross = -0.05;
    auto layers = emptyLayers(cam);
    b.draw(pose, nullptr, cam, lookingAlongY(), 15, 7, layers);
    const Eigen::Matrix3d R = lookingAlongY().getRotationMatrix().asEigen();
    const Eigen::Vector3d across = pose.across();
    int checked = 0;
    double nearest = 10.0;
    std::vector<double> errors;
    for (int v = 0; v < cam.height; v++)
    {
        for (int u = 0; u < cam.width; u++)
        {
            if (layers.instances.at<uint16_t>(v, u) == 0)
                continue;
            // The pixel's world point, expressed in the billboard's frame, is surfacePoint() of
            // its own sprite coordinates (found from its height and lateral position).
            const Eigen::Vector3d X = R * cam.unproject(u, v, layers.depth.at<float>(v, u));
            const Eigen::Vector3d rel = X - pose.feet;
            const double y = pose.up.dot(rel);
            const double above = std::max(0.0, y - pose.pivotHeight);
            const double a =
                (across.dot(rel) - above * std::tan(pose.leanAcross)) / (pose.height * 0.5) + 0.5;
            const Eigen::Vector3d S = b.surfacePoint(pose, a, 1.0 - y / pose.height);
            errors.push_back((S - X).norm());
            nearest = std::min(nearest, static_cast<double>(layers.depth.at<float>(v, u)));
            checked++;
        }
    }
    EXPECT_GT(checked, 1500);
    // On the surface: the fixed-point steps converge except right at the silhouette, where
    // the elliptic profile is steepest.
    std::sort(errors.begin(), errors.end());
    EXPECT_LT(errors[errors.size() * 99 / 100], 1e-3);
    EXPECT_LT(errors.back(), 0.01);
    // The relief and the lean bring the body towards the camera: nearer than the plane at 3 m.
    EXPECT_LT(nearest, 3.0 - 0.1);
}

TEST(SpriteBillboard, OnlyWhatMovedIsDynamic)
{
    const auto cam = test::centredCamera(320, 240, 250.0);
    const sim::SpriteBillboard b(rectangleSprite(), {0.12, true});
    auto pose = poseAhead();
    pose.pivotHeight = 0.9;
    auto before = pose;
    before.leanTowards = 0.02;  // the upper body moved, the legs did not
    auto layers = emptyLayers(cam);
    b.draw(pose, &before, cam, lookingAlongY(), 15, 7, layers);
    const int person = cv::countNonZero(layers.instances);
    const int moving = cv::countNonZero(layers.dynamic);
    EXPECT_GT(moving, person / 4);
    EXPECT_LT(moving, person * 3 / 4);
    // Below the pivot (lower image rows), nothing moved.
    const int pivotRow = static_cast<int>(cam.cy + 250.0 * (1.2 - 0.9) / 3.0) + 2;
    EXPECT_EQ(cv::countNonZero(layers.dynamic.rowRange(pivotRow, cam.height)), 0);
    EXPECT_GT(cv::countNonZero(layers.instances.rowRange(pivotRow, cam.height)), 500);
}
