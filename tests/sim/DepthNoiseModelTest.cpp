#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/sim/DepthNoiseModel.h"

using smap::sim::DepthNoiseModel;

namespace
{
smap::core::PinholeCamera camera()
{
    return smap::test::centredCamera(200, 150, 525.0);
}
}  // namespace

TEST(DepthNoiseModel, PlaneNoiseHasTheModelledSpread)
{
    // Fronto-parallel plane at 2 m, bright: only axial noise and disparity quantisation apply.
    const cv::Mat depth(150, 200, CV_32FC1, cv::Scalar(2.0f));
    const cv::Mat colour(150, 200, CV_8UC3, cv::Scalar(200, 200, 200));
    DepthNoiseModel m;
    std::mt19937 rng(3);
    const cv::Mat noisy = m.apply(depth, colour, camera(), rng);
    cv::Scalar mean, stddev;
    cv::meanStdDev(noisy, mean, stddev, noisy > 0);
    const double sigma = DepthNoiseModel::sigma(2.0);      // 6.06 mm
    const double step = 4.0 / (525 * 0.075) * m.subpixel;  // 12.7 mm quantum at 2 m
    const double expected = std::sqrt(sigma * sigma + step * step / 12.0);
    EXPECT_NEAR(stddev[0], expected, 0.15 * expected);
    EXPECT_NEAR(mean[0], 2.0, 0.002);
    EXPECT_GT(cv::countNonZero(noisy), 0.99 * noisy.total());
}

TEST(DepthNoiseModel, HolesAtSilhouettesDarknessAndRange)
{
    cv::Mat depth(150, 200, CV_32FC1, cv::Scalar(3.0f));
    depth.colRange(0, 100).setTo(1.0f);  // a 2 m step at column 100
    depth.at<float>(10, 150) = 0.2f;     // nearer than the minimum range
    cv::Mat colour(150, 200, CV_8UC3, cv::Scalar(200, 200, 200));
    colour.rowRange(120, 150).setTo(cv::Scalar(5, 5, 5));  // very dark stripe
    DepthNoiseModel m;
    std::mt19937 rng(5);
    const cv::Mat noisy = m.apply(depth, colour, camera(), rng);
    const double edgeHoles = 1.0 - cv::countNonZero(noisy.col(100)) / 150.0;
    const double darkHoles =
        1.0 - cv::countNonZero(noisy.rowRange(120, 150).colRange(20, 80)) / (30.0 * 60.0);
    EXPECT_GT(edgeHoles, 0.4);
    EXPECT_NEAR(darkHoles, m.holeProbabilityDark, 0.05);
    EXPECT_EQ(noisy.at<float>(10, 150), 0.0f);
    m.enabled = false;
    EXPECT_EQ(cv::norm(m.apply(depth, colour, camera(), rng), depth, cv::NORM_INF), 0.0);
}
