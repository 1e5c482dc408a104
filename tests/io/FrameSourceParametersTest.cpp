#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/FrameSourceParameters.h"

using namespace smap;

namespace
{
const char* kCameras = R"(
[camera]
width = 640
height = 480
fx = 525.5
fy = 525.5
cx = 320
cy = 240
[depth_camera]
width = 320
height = 240
fx = 292.5
fy = 292.5
cx = 160
cy = 120
)";

io::FrameSourceParameters load(const std::string& extra)
{
    core::TrackedConfig cfg;
    cfg.loadText(std::string(kCameras) + extra, "test.ini");
    io::FrameSourceParameters p;
    cfg.load(p);
    cfg.ensureAllKeysUsed();
    return p;
}

std::string errorOf(const std::string& extra)
{
    try
    {
        load(extra);
    }
    catch (const core::InputError& e)
    {
        return e.what();
    }
    return "no error";
}
}  // namespace

TEST(FrameSourceParameters, DepthCameraAndExtrinsicAreRead)
{
    const auto p = load("t_colour_depth = -0.025, 0.001 0.002\nr_colour_depth = 0 0 90\n");
    ASSERT_TRUE(p.depth_camera.has_value());
    EXPECT_EQ(p.depth_camera->width, 320);
    EXPECT_EQ(p.depth_camera->fx, 292.5);
    EXPECT_EQ(p.camera->fx, 525.5);
    EXPECT_TRUE(p.T_colour_depth.translation().isApprox(Eigen::Vector3d(-0.025, 0.001, 0.002)));
    // 90 degrees about z: the depth camera's x axis is the colour camera's y axis.
    const Eigen::Vector3d x = p.T_colour_depth.linear() * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(x.y(), 1.0, 1e-12);
    EXPECT_NEAR(x.x(), 0.0, 1e-12);
}

TEST(FrameSourceParameters, WithoutExtrinsicTheCamerasCoincide)
{
    const auto p = load("");
    ASSERT_TRUE(p.depth_camera.has_value());
    EXPECT_TRUE(p.T_colour_depth.isApprox(Eigen::Isometry3d::Identity()));
    io::FrameSourceParameters none;
    core::TrackedConfig empty;
    empty.load(none);
    EXPECT_FALSE(none.depth_camera.has_value());
}

TEST(FrameSourceParameters, SavedParametersLoadBackTheSame)
{
    const auto p = load("t_colour_depth = -0.025 0.001 0.002\nr_colour_depth = 1 -2 3\n");
    mrpt::config::CConfigFileMemory saved;
    p.saveToConfigFile(saved, "");
    io::FrameSourceParameters q;
    q.loadFromConfigFile(saved, "");
    ASSERT_TRUE(q.depth_camera.has_value());
    EXPECT_EQ(*q.depth_camera, *p.depth_camera);
    EXPECT_TRUE(q.T_colour_depth.isApprox(p.T_colour_depth, 1e-12));
}

TEST(FrameSourceParameters, BadExtrinsicsAreErrorsNamingTheKeyAndValue)
{
    EXPECT_NE(errorOf("t_colour_depth = -0.025 0\n")
                  .find("[depth_camera] t_colour_depth = "
                        "'-0.025 0' must be three numbers"),
              std::string::npos);
    EXPECT_NE(errorOf("r_colour_depth = 0 0 x\n").find("r_colour_depth = '0 0 x'"),
              std::string::npos);
    EXPECT_NE(errorOf("t_colour_depth = -25 0 0\n").find("25.00 m apart (metres expected)"),
              std::string::npos);
    EXPECT_NE(errorOf("t_colour_depht = 0 0 0\n").find("t_colour_depht"), std::string::npos);
}
