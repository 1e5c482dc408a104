#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "smap/io/DepthRegistration.h"

using smap::core::PinholeCamera;
using smap::io::DepthRegistration;

namespace
{
PinholeCamera cam(double f, double cx, double cy)
{
    PinholeCamera c;
    c.width = 320;
    c.height = 240;
    c.fx = c.fy = f;
    c.cx = cx;
    c.cy = cy;
    return c;
}

Eigen::Isometry3d translation(double x)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(x, 0, 0);
    return T;
}

std::pair<int, int> validColumnRange(const cv::Mat& d, int row)
{
    int first = -1, last = -1;
    for (int u = 0; u < d.cols; u++)
    {
        if (d.at<float>(row, u) > 0)
        {
            if (first < 0)
                first = u;
            last = u;
        }
    }
    return {first, last};
}
}  // namespace

TEST(DepthRegistration, PlaneSeenFromShiftedCameraHasHandComputedExtent)
{
    // Colour camera 5 cm to the right of the depth camera: p_colour = p_depth - (0.05, 0, 0).
    // A fronto-parallel plane at z = 2 m: u_c = 400 * ((u_d - 159.5) / 500 * 2 - 0.05) / 2 + 160.
    const DepthRegistration reg(cam(500, 159.5, 119.5), cam(400, 160, 120), translation(-0.05));
    const cv::Mat depth(240, 320, CV_32FC1, cv::Scalar(2.0f));
    const cv::Mat out = reg.registerDepth(depth);
    EXPECT_EQ(out.at<float>(120, 150), 2.0f);
    const auto [first, last] = validColumnRange(out, 120);
    EXPECT_EQ(first, 22);  // u_d = 0   -> 22.4
    EXPECT_EQ(last, 278);  // u_d = 319 -> 277.6
    // Rows: v_c = 0.8 (v_d - 119.5) + 120 -> 24.4 .. 215.6.
    EXPECT_EQ(out.at<float>(23, 150), 0.0f);
    EXPECT_EQ(out.at<float>(24, 150), 2.0f);
    EXPECT_EQ(out.at<float>(216, 150), 2.0f);
    EXPECT_EQ(out.at<float>(217, 150), 0.0f);
    // Every covered colour pixel is reached (the depth grid is denser than the colour grid).
    for (int u = first; u <= last; u++)
        EXPECT_GT(out.at<float>(120, u), 0.0f) << u;
}

TEST(DepthRegistration, NearestSurfaceWinsWhereTwoLandOnOnePixel)
{
    // Colour camera 5 cm to the left: near points shift right by 20 px, far (3 m) by 6.7 px, so
    // the near left half overlaps the far right half between columns 167 and 179.
    const DepthRegistration reg(cam(500, 159.5, 119.5), cam(400, 160, 120), translation(+0.05));
    cv::Mat depth(240, 320, CV_32FC1, cv::Scalar(3.0f));
    depth.colRange(0, 160).setTo(1.0f);
    const cv::Mat out = reg.registerDepth(depth);
    EXPECT_EQ(out.at<float>(120, 175), 1.0f);
    EXPECT_EQ(out.at<float>(120, 185), 3.0f);
    EXPECT_EQ(out.at<float>(120, 150), 1.0f);
}

TEST(DepthRegistration, IdentityKeepsDepthAndInvalidPixels)
{
    const PinholeCamera c = cam(500, 159.5, 119.5);
    const DepthRegistration reg(c, c, Eigen::Isometry3d::Identity());
    cv::Mat depth(240, 320, CV_32FC1);
    cv::randu(depth, 0.5, 4.0);
    depth.at<float>(10, 10) = 0.0f;
    const cv::Mat out = reg.registerDepth(depth);
    EXPECT_LT(cv::norm(out, depth, cv::NORM_INF), 1e-6);
    EXPECT_EQ(out.at<float>(10, 10), 0.0f);
}
