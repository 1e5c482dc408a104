// Back-projection (eq. 5) with known answers: positions, colour, label and confidence, the
// dynamic mask, depth range, stride and lens distortion.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "smap/core/RgbdFrame.h"
#include "smap/maps/BackProjector.h"

using namespace smap;
using maps::BackProjectionParameters;
using maps::BackProjector;

namespace
{
core::RgbdFrame frame(int w = 40, int h = 30, float z = 2.0f)
{
    core::RgbdFrame f;
    f.camera.width = w;
    f.camera.height = h;
    f.camera.fx = f.camera.fy = 50.0;
    f.camera.cx = (w - 1) / 2.0;
    f.camera.cy = (h - 1) / 2.0;
    f.colour = cv::Mat(h, w, CV_8UC3, cv::Scalar(10, 20, 30));
    f.depth = cv::Mat(h, w, CV_32FC1, cv::Scalar(z));
    return f;
}

BackProjector::Images images(const core::RgbdFrame& f, int label, float p,
                             const cv::Mat& mask = cv::Mat())
{
    BackProjector::Images im;
    im.colour = f.colour;
    im.depth = f.depth;
    im.labels = cv::Mat(f.depth.size(), CV_8UC1, cv::Scalar(label));
    im.confidence = cv::Mat(f.depth.size(), CV_32FC1, cv::Scalar(p));
    im.dynamicMask = mask;
    return im;
}
}  // namespace

TEST(BackProjector, KnownPointsInTheWorld)
{
    auto f = frame();
    f.depth.at<float>(0, 0) = 1.0f;
    // Camera 1 m up, rotated 90 degrees about z (yaw).
    const mrpt::poses::CPose3D T_world_cam(0.0, 0.0, 1.0, M_PI / 2, 0.0, 0.0);
    BackProjector bp{BackProjectionParameters()};
    const auto pts = bp.project(images(f, 15, 0.8f), f.camera, T_world_cam);
    ASSERT_EQ(pts.size(), 40u * 30u);
    // Pixel (0, 0) at 1 m: X_cam = ((0 - 19.5) / 50, (0 - 14.5) / 50, 1).
    const auto& p = pts[0];
    EXPECT_EQ(p.u, 0);
    EXPECT_EQ(p.v, 0);
    const double xc = -19.5 / 50.0, yc = -14.5 / 50.0, zc = 1.0;
    // yaw 90: world = (-y_cam, x_cam, z_cam) + t.
    EXPECT_NEAR(p.position.x(), -yc, 1e-6);
    EXPECT_NEAR(p.position.y(), xc, 1e-6);
    EXPECT_NEAR(p.position.z(), zc + 1.0, 1e-6);
    EXPECT_EQ(p.r, 30);
    EXPECT_EQ(p.g, 20);
    EXPECT_EQ(p.b, 10);
    EXPECT_EQ(p.label, 15);
    EXPECT_NEAR(p.confidence, 0.8f, 1e-6);
}

TEST(BackProjector, MaskRangeAndStride)
{
    auto f = frame();
    f.depth(cv::Rect(0, 0, 10, 30)).setTo(0.2f);  // too near
    f.depth(cv::Rect(10, 0, 5, 30)).setTo(5.0f);  // too far
    f.depth(cv::Rect(15, 0, 5, 30)).setTo(0.0f);  // no depth
    cv::Mat mask = cv::Mat::zeros(30, 40, CV_8UC1);
    mask(cv::Rect(20, 0, 10, 30)).setTo(255);  // dynamic
    BackProjector bp{BackProjectionParameters()};
    const auto pts = bp.project(images(f, 0, 0.9f, mask), f.camera, mrpt::poses::CPose3D());
    EXPECT_EQ(pts.size(), 10u * 30u);  // columns 30-39 only
    for (const auto& p : pts)
        EXPECT_GE(p.u, 30);
    BackProjectionParameters every3;
    every3.stride = 3;
    BackProjector sparse(every3);
    // u = 30, 33, 36, 39 and v = 0, 3, ..., 27.
    EXPECT_EQ(sparse.project(images(f, 0, 0.9f, mask), f.camera, mrpt::poses::CPose3D()).size(),
              4u * 10u);
}

TEST(BackProjector, UndoesLensDistortion)
{
    auto f = frame(64, 48, 1.5f);
    f.camera.distortion = {0.2, -0.1, 0.001, -0.002, 0.0};
    BackProjector bp{BackProjectionParameters()};
    const auto pts = bp.project(images(f, 9, 0.7f), f.camera, mrpt::poses::CPose3D());
    ASSERT_EQ(pts.size(), 64u * 48u);
    // Reprojecting each point with the distorted camera lands on its pixel.
    std::vector<cv::Point3f> objects;
    for (const auto& p : pts)
        objects.emplace_back(p.position.x(), p.position.y(), p.position.z());
    std::vector<cv::Point2f> image;
    cv::projectPoints(objects, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), f.camera.cameraMatrix(),
                      f.camera.distCoeffs(), image);
    double worst = 0.0;
    for (size_t i = 0; i < pts.size(); i++)
        worst = std::max(worst, double(std::hypot(image[i].x - pts[i].u, image[i].y - pts[i].v)));
    EXPECT_LT(worst, 0.01);
    EXPECT_NEAR(pts[0].position.z(), 1.5f, 1e-6);
}
