// Ground truth of the rendered sequences checked against geometry, not against itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;

namespace
{
sim::GeneratorOptions options(const std::string& preset, bool noiseFree = true, uint32_t seed = 1)
{
    sim::GeneratorOptions o;
    o.preset = preset;
    o.noiseFreeDepth = noiseFree;
    o.seed = seed;
    return o;
}

double median(std::vector<double> v)
{
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

/// |depth of B - depth of A's static pixels moved into B| for pixels visible in both.
std::vector<double> reprojectionErrors(const sim::SyntheticFrame& a, const sim::SyntheticFrame& b,
                                       const core::PinholeCamera& cam)
{
    std::vector<double> errors;
    const mrpt::poses::CPose3D T_b_a = a.T_world_cam - b.T_world_cam;  // inv(T_world_b) * T_world_a
    for (int v = 0; v < cam.height; v += 2)
    {
        for (int u = 0; u < cam.width; u += 2)
        {
            const double z = a.depthNoiseFree.at<float>(v, u);
            if (z <= 0 || a.rendered.dynamic.at<uint8_t>(v, u))
                continue;
            const Eigen::Vector3d pa = cam.unproject(u, v, z);
            double x, y, zb;
            T_b_a.composePoint(pa.x(), pa.y(), pa.z(), x, y, zb);
            if (zb <= 0.1)
                continue;
            const Eigen::Vector2d uv = cam.project({x, y, zb});
            const long ub = std::lround(uv.x()), vb = std::lround(uv.y());
            if (ub < 0 || vb < 0 || ub >= cam.width || vb >= cam.height)
                continue;
            const double measured =
                b.depthNoiseFree.at<float>(static_cast<int>(vb), static_cast<int>(ub));
            if (measured <= 0 ||
                b.rendered.dynamic.at<uint8_t>(static_cast<int>(vb), static_cast<int>(ub)))
                continue;
            if (measured < zb - 0.05)
                continue;  // occluded in B
            errors.push_back(std::abs(measured - zb));
        }
    }
    return errors;
}
}  // namespace

TEST(SyntheticSequence, FloorDepthMatchesRayPlaneIntersection)
{
    sim::SequenceGenerator gen(options("static_static"));
    const auto f = gen.frame(0);
    const auto& cam = gen.options().camera;
    const auto R = f.T_world_cam.getRotationMatrix();
    size_t checked = 0;
    std::vector<double> errors;
    for (int v = 440; v < 480; v += 7)
    {
        for (int u = 5; u < 640; u += 37)
        {
            if (f.rendered.instances.at<uint16_t>(v, u) != 1)
                continue;  // instance 1 is the floor
            // Ray through the pixel centre, intersected with the floor plane z = 0.
            const Eigen::Vector3d dCam((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
            Eigen::Vector3d dWorld;
            for (int r = 0; r < 3; r++)
                dWorld[r] = R(r, 0) * dCam.x() + R(r, 1) * dCam.y() + R(r, 2) * dCam.z();
            const double s = -f.T_world_cam.z() / dWorld.z();  // depth = s since dCam.z = 1
            errors.push_back(std::abs(f.depthNoiseFree.at<float>(v, u) - s));
            checked++;
        }
    }
    ASSERT_GT(checked, 50u);
    EXPECT_LT(*std::max_element(errors.begin(), errors.end()), 0.003);
    EXPECT_EQ(f.rendered.labels.at<uint8_t>(470, 320), 0);
}

TEST(SyntheticSequence, StaticPixelsReprojectOntoTheOtherFramesDepth)
{
    for (const char* preset : {"static_halfsphere", "walking_xyz"})
    {
        sim::SequenceGenerator gen(options(preset));
        const auto a = gen.frame(3);
        const auto b = gen.frame(18);
        const auto e = reprojectionErrors(a, b, gen.options().camera);
        ASSERT_GT(e.size(), 20000u) << preset;
        EXPECT_LT(median(e), 0.005) << preset;
        const double within1cm = static_cast<double>(std::count_if(
                                     e.begin(), e.end(), [](double x) { return x < 0.01; })) /
                                 e.size();
        EXPECT_GT(within1cm, 0.9) << preset;
        RecordProperty(std::string("median_reprojection_error_m_") + preset,
                       std::to_string(median(e)));
    }
}

TEST(SyntheticSequence, LabelsMatchInstancesAndDynamicMaskCoversWalkers)
{
    sim::SequenceGenerator gen(options("walking_static"));
    const auto& classes = gen.scene().instanceClasses();
    size_t people = 0;
    for (size_t i : {0u, 20u, 40u})
    {
        const auto f = gen.frame(i);
        for (int v = 0; v < 480; v++)
        {
            for (int u = 0; u < 640; u++)
            {
                const uint16_t id = f.rendered.instances.at<uint16_t>(v, u);
                const uint8_t label = f.rendered.labels.at<uint8_t>(v, u);
                ASSERT_NE(id, 0) << "closed room: every pixel shows an object";
                ASSERT_EQ(classes.at(id), label) << u << "," << v;
                // Walkers move all the time: the mask is exactly the person pixels.
                ASSERT_EQ(f.rendered.dynamic.at<uint8_t>(v, u) != 0, label == sim::voc::kPerson)
                    << u << "," << v;
                people += label == sim::voc::kPerson;
            }
        }
    }
    EXPECT_GT(people, 5000u);
}

TEST(SyntheticSequence, SittingPeopleMoveOnlyInTheirMovingParts)
{
    sim::SequenceGenerator gen(options("sitting_xyz"));
    const auto f = gen.frame(10);
    const cv::Mat person = f.rendered.labels == sim::voc::kPerson;
    const cv::Mat dynamicNotPerson = (f.rendered.dynamic != 0) & ~person;
    EXPECT_EQ(cv::countNonZero(dynamicNotPerson), 0);
    const int moving = cv::countNonZero(f.rendered.dynamic);
    EXPECT_GT(moving, 0);                         // torso sway, gestures
    EXPECT_LT(moving, cv::countNonZero(person));  // legs rest on the chair
}

TEST(SyntheticSequence, PeopleNeedTheCutOutsAndSayWhere)
{
    auto o = options("walking_xyz");
    o.peopleDirectory.clear();
    EXPECT_NE(test::inputErrorOf([&] { sim::SequenceGenerator g(o); }).find("cut-outs"),
              std::string::npos);
    o.peopleDirectory = "/nonexistent/people";
    EXPECT_NE(test::inputErrorOf([&] { sim::SequenceGenerator g(o); }).find("/nonexistent/people"),
              std::string::npos);
    o.preset = "static_xyz";  // nobody in the room: no cut-outs needed
    EXPECT_NO_THROW(sim::SequenceGenerator g(o));
}

TEST(SyntheticSequence, DeterministicForASeed)
{
    sim::SequenceGenerator a(options("walking_rpy", false, 7)), b(options("walking_rpy", false, 7)),
        c(options("walking_rpy", false, 8));
    const auto fa = a.frame(5), fb = b.frame(5), fc = c.frame(5);
    EXPECT_EQ(cv::norm(fa.rendered.colour, fb.rendered.colour, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(fa.rendered.depth, fb.rendered.depth, cv::NORM_INF), 0.0);
    EXPECT_GT(cv::norm(fa.rendered.colour, fc.rendered.colour, cv::NORM_L1), 0.0);
    EXPECT_THROW(sim::SequenceGenerator(options("walking_nowhere")), core::InputError);
}

TEST(SyntheticSequence, RgbdFrameIsTheFrameWithTheOptionsCamera)
{
    sim::SequenceGenerator a(options("walking_rpy", false, 7)), b(options("walking_rpy", false, 7));
    const auto f = a.frame(5);
    const core::RgbdFrame r = b.rgbdFrame(5);
    EXPECT_EQ(cv::norm(f.rendered.colour, r.colour, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(f.rendered.depth, r.depth, cv::NORM_INF), 0.0);  // the sensor's depth
    EXPECT_GT(cv::norm(f.depthNoiseFree, r.depth, cv::NORM_L1), 0.0);
    EXPECT_EQ(r.timestamp, f.timestamp);
    EXPECT_EQ(r.camera.fx, b.options().camera.fx);
    EXPECT_EQ(r.camera.width, b.options().camera.width);
}
