#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <vector>

#include "smap/core/InputError.h"
#include "smap/core/PinholeCamera.h"

using smap::core::PinholeCamera;

namespace
{
PinholeCamera sampleCamera()
{
    PinholeCamera c;
    c.width = 640;
    c.height = 480;
    c.fx = 517.3;
    c.fy = 516.5;
    c.cx = 318.6;
    c.cy = 255.3;
    c.distortion = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
    return c;
}
}  // namespace

TEST(PinholeCamera, ProjectInvertsUnproject)
{
    const PinholeCamera c = sampleCamera();
    const Eigen::Vector3d p = c.unproject(100.25, 400.5, 2.5);
    EXPECT_DOUBLE_EQ(p.z(), 2.5);
    EXPECT_NEAR(p.x(), (100.25 - 318.6) * 2.5 / 517.3, 1e-15);
    const Eigen::Vector2d uv = c.project(p);
    EXPECT_NEAR(uv.x(), 100.25, 1e-10);
    EXPECT_NEAR(uv.y(), 400.5, 1e-10);
    // A point on the optical axis lands on the principal point.
    EXPECT_NEAR(c.project({0, 0, 3}).x(), c.cx, 1e-12);
}

TEST(PinholeCamera, DistortionMatchesTheUndistortionItInverts)
{
    // Undistorting a distorted point (OpenCV's plumb-bob model, iterated) gives it back; a
    // camera without distortion leaves the point alone.
    const PinholeCamera c = sampleCamera();
    double x = 0.31, y = -0.22;
    c.distortNormalised(x, y);
    const std::vector<cv::Point2d> distorted = {{c.fx * x + c.cx, c.fy * y + c.cy}};
    std::vector<cv::Point2d> undistorted;
    cv::undistortPoints(
        distorted, undistorted, c.cameraMatrix(), c.distCoeffs(), cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
    EXPECT_NEAR(undistorted[0].x, 0.31, 1e-6);
    EXPECT_NEAR(undistorted[0].y, -0.22, 1e-6);
    EXPECT_GT(std::abs(x - 0.31), 1e-3) << "the sample camera does distort";
    PinholeCamera plain = c;
    plain.distortion = {};
    float u = 0.31F, v = -0.22F;
    plain.distortNormalised(u, v);
    EXPECT_EQ(u, 0.31F);
    EXPECT_EQ(v, -0.22F);
}

TEST(PinholeCamera, MrptRoundTrip)
{
    const PinholeCamera c = sampleCamera();
    const auto m = c.toMrpt();
    EXPECT_DOUBLE_EQ(m.fx(), 517.3);
    EXPECT_DOUBLE_EQ(m.dist[4], 1.1633);
    EXPECT_EQ(PinholeCamera::fromMrpt(m), c);
}

TEST(PinholeCamera, ConfigRoundTripAndErrors)
{
    mrpt::config::CConfigFileMemory cfg;
    smap::core::saveCamera(sampleCamera(), cfg, "camera");
    EXPECT_EQ(smap::core::loadCamera(cfg, "camera"), sampleCamera());

    mrpt::config::CConfigFileMemory partial(
        "[camera]\nwidth=640\nheight=480\nfx=500\nfy=500\ncx=320\n");
    try
    {
        smap::core::loadCamera(partial, "camera");
        FAIL();
    }
    catch (const smap::core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("'cy'"), std::string::npos) << e.what();
    }
    mrpt::config::CConfigFileMemory bad(
        "[camera]\nwidth=640\nheight=480\nfx=-1\nfy=500\ncx=320\ncy=240\n");
    EXPECT_THROW(smap::core::loadCamera(bad, "camera"), smap::core::InputError);
}
