// Compositing checked against known geometry: the "real" sequence is a rendered one, whose
// floor (z = 0), up (+z) and poses are exact.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "smap/core/InputError.h"
#include "smap/sim/PeopleCompositor.h"
#include "smap/sim/SequenceGenerator.h"

using namespace smap;

namespace
{
cv::Mat ellipseSprite()
{
    cv::Mat s(120, 40, CV_8UC4, cv::Scalar(0, 0, 0, 0));
    cv::ellipse(s, {20, 60}, {19, 59}, 0, 0, 360, cv::Scalar(40, 160, 220, 255), cv::FILLED);
    return s;
}

struct RealSequence
{
    std::vector<sim::SyntheticFrame> frames;
    core::Trajectory trajectory;
    core::PinholeCamera camera;
};

RealSequence renderStaticSequence()
{
    sim::GeneratorOptions o;
    o.preset = "static_halfsphere";
    o.noiseFreeDepth = true;
    sim::SequenceGenerator gen(o);
    RealSequence r;
    r.camera = o.camera;
    for (size_t i = 0; i <= 90; i += 10)
    {
        r.frames.push_back(gen.frame(i));
        r.trajectory.push_back({r.frames.back().timestamp, r.frames.back().T_world_cam});
    }
    return r;
}

core::RgbdFrame asRgbd(const sim::SyntheticFrame& f, const core::PinholeCamera& cam)
{
    core::RgbdFrame r;
    r.colour = f.rendered.colour;
    r.depth = f.depthNoiseFree;
    r.camera = cam;
    r.timestamp = f.timestamp;
    return r;
}
}  // namespace

TEST(PeopleCompositor, StopAndStayStandsStillForItsDwellAndSwayStaysInPlace)
{
    sim::CompositedPerson p;
    p.start = {0, 0, 0};
    p.direction = {1, 0, 0};
    p.halfRange = 1.0;
    p.speed = 1.0;
    p.dwell = 5.0;
    // Walks from -1 to +1 in 2 s, stands 5 s, walks back in 2 s, stands 5 s: period 14 s.
    EXPECT_NEAR(p.feetAt(0.0).x(), -1.0, 1e-12);
    EXPECT_NEAR(p.feetAt(1.0).x(), 0.0, 1e-9);
    for (double t = 2.0; t <= 7.0; t += 0.5)
        EXPECT_NEAR(p.feetAt(t).x(), 1.0, 1e-9) << "standing at t = " << t;
    EXPECT_NEAR(p.feetAt(8.0).x(), 0.0, 1e-9);
    for (double t = 9.0; t < 14.0; t += 0.5)
        EXPECT_NEAR(p.feetAt(t).x(), -1.0, 1e-9) << "standing at t = " << t;
    EXPECT_NEAR(p.feetAt(15.0).x(), 0.0, 1e-9) << "next period";

    sim::CompositedPerson s;
    s.start = {0, 3, 0};
    s.direction = {1, 0, 0};
    s.sway = true;
    s.halfRange = 0.1;
    s.swayPeriod = 2.0;
    EXPECT_NEAR(s.feetAt(0.5).x(), 0.1, 1e-9);  // a quarter period: the far side
    EXPECT_NEAR(s.feetAt(1.5).x(), -0.1, 1e-9);
    for (double t = 0; t < 10; t += 0.37)
        EXPECT_LE((s.feetAt(t) - s.start).norm(), 0.1 + 1e-9);
}

TEST(PeopleCompositor, ScenariosByNameWithTheirPeopleCounts)
{
    for (const auto* name : {"random", "crossing", "crowd", "seated", "stop_and_stay"})
        EXPECT_EQ(sim::toString(sim::compositeScenarioFromString(name)), name);
    EXPECT_EQ(sim::defaultPeopleCount(sim::CompositeScenario::Crowd), 3u);
    EXPECT_EQ(sim::defaultPeopleCount(sim::CompositeScenario::StopAndStay), 1u);
    EXPECT_THROW(sim::compositeScenarioFromString("dance"), core::InputError);
}

TEST(PeopleCompositor, ACrowdGathersCloseInFrontOfTheMiddleFrame)
{
    const RealSequence real = renderStaticSequence();
    std::vector<sim::PeopleCompositor::Probe> probes;
    for (const auto& f : real.frames)
        probes.push_back({asRgbd(f, real.camera), f.T_world_cam});
    const sim::PeopleCompositor comp({ellipseSprite()}, real.trajectory, probes, 3, 3,
                                     sim::CompositeLayout{sim::CompositeScenario::Crowd});
    ASSERT_EQ(comp.people().size(), 3u);
    const auto& middle = probes[probes.size() / 2].T_world_cam;
    const Eigen::Vector3d c(middle.x(), middle.y(), middle.z());
    for (const auto& p : comp.people())
    {
        Eigen::Vector3d d = p.start - c;
        d -= comp.up() * comp.up().dot(d);
        EXPECT_LE(d.norm(), 1.6 * 1.01 + 0.6) << "within 1.6 m ahead and 0.6 m aside";
        EXPECT_GE(p.speed, 1.3);
    }
}

namespace
{
/// How far ahead of the middle probe (along its view on the floor) each person starts.
std::vector<double> distancesAheadOfTheMiddleFrame(double distanceScale)
{
    const RealSequence real = renderStaticSequence();
    std::vector<sim::PeopleCompositor::Probe> probes;
    for (const auto& f : real.frames)
        probes.push_back({asRgbd(f, real.camera), f.T_world_cam});
    sim::CompositeLayout layout;
    layout.scenario = sim::CompositeScenario::Crowd;
    layout.distanceScale = distanceScale;
    const sim::PeopleCompositor comp({ellipseSprite()}, real.trajectory, probes, 3, 3, layout);
    const auto& middle = probes[probes.size() / 2].T_world_cam;
    const Eigen::Vector3d c(middle.x(), middle.y(), middle.z());
    Eigen::Vector3d forward = middle.getRotationMatrix().asEigen().col(2);
    forward -= comp.up() * comp.up().dot(forward);
    forward.normalize();
    std::vector<double> ahead;
    for (const auto& p : comp.people())
        ahead.push_back(forward.dot(p.start - c));
    return ahead;
}
}  // namespace

TEST(PeopleCompositor, TheDistanceScaleMovesTheCrowdFurtherAhead)
{
    // The crowd starts 0.9 - 1.6 m ahead; scaled by 2, 1.8 - 3.2 m.
    for (const double ahead : distancesAheadOfTheMiddleFrame(1.0))
    {
        EXPECT_GE(ahead, 0.9 - 1e-6);
        EXPECT_LE(ahead, 1.6 + 1e-6);
    }
    for (const double ahead : distancesAheadOfTheMiddleFrame(2.0))
    {
        EXPECT_GE(ahead, 1.8 - 1e-6);
        EXPECT_LE(ahead, 3.2 + 1e-6);
    }
    EXPECT_THROW(distancesAheadOfTheMiddleFrame(0.0), core::InputError);
}

TEST(PeopleCompositor, PeopleStandOnTheFloorInFreeSpaceWithCorrectOcclusion)
{
    const RealSequence real = renderStaticSequence();
    std::vector<sim::PeopleCompositor::Probe> probes;
    for (const auto& f : real.frames)
        probes.push_back({asRgbd(f, real.camera), f.T_world_cam});
    const sim::PeopleCompositor comp({ellipseSprite()}, real.trajectory, probes, 2, 3);

    // The floor fit recovers the world's up and floor although the camera looks down ~11 deg.
    EXPECT_GT(comp.up().dot(Eigen::Vector3d::UnitZ()), std::cos(1.0 * M_PI / 180.0));
    EXPECT_NEAR(comp.floorHeight(), 0.0, 0.01);
    EXPECT_EQ(comp.freeSpaceViolations(), 0u);

    size_t personPixels = 0;
    for (size_t k = 0; k < real.frames.size(); k++)
    {
        const auto& f = real.frames[k];
        const double t = f.timestamp - real.frames.front().timestamp;
        const auto c = comp.composite(asRgbd(f, real.camera), f.T_world_cam, t);
        ASSERT_EQ(c.objectPoses.size(), 2u);
        const Eigen::Matrix3d R = f.T_world_cam.getRotationMatrix().asEigen();
        const Eigen::Vector3d cw(f.T_world_cam.x(), f.T_world_cam.y(), f.T_world_cam.z());
        for (int v = 0; v < c.depth.rows; v++)
        {
            for (int u = 0; u < c.depth.cols; u++)
            {
                const uint16_t id = c.instances.at<uint16_t>(v, u);
                ASSERT_EQ(c.labels.at<uint8_t>(v, u),
                          id ? 15 : sim::PeopleCompositor::kUnknownLabel);
                ASSERT_EQ(c.dynamic.at<uint8_t>(v, u) != 0, id != 0);
                if (id == 0)
                {
                    ASSERT_EQ(c.depth.at<float>(v, u), f.depthNoiseFree.at<float>(v, u));
                    continue;
                }
                personPixels++;
                const float z = c.depth.at<float>(v, u);
                // Nothing real was in front of the person here.
                const float z0 = f.depthNoiseFree.at<float>(v, u);
                ASSERT_TRUE(z0 == 0.0f || z0 >= z) << u << "," << v;
                // The pixel lies on the person's body: between floor and head, within half
                // a width of the vertical axis through the feet.
                const auto& p = comp.people().at(id - 1);
                const Eigen::Vector3d X = R * real.camera.unproject(u, v, z) + cw - p.feetAt(t);
                const double h = X.dot(Eigen::Vector3d::UnitZ());
                const double width = p.height * p.sprite.cols / p.sprite.rows;
                ASSERT_GT(h, -0.01);
                ASSERT_LT(h, p.height + 0.01);
                ASSERT_LT(Eigen::Vector2d(X.x(), X.y()).norm(), width / 2 + 0.01);
            }
        }
        // Recorded root poses are the feet positions.
        for (size_t i = 0; i < 2; i++)
        {
            const Eigen::Vector3d feet = comp.people()[i].feetAt(t);
            const auto& pose = c.objectPoses[i].second;
            EXPECT_LT((Eigen::Vector3d(pose.x(), pose.y(), pose.z()) - feet).norm(), 1e-9);
        }
    }
    EXPECT_GT(personPixels, 2000u);
}

TEST(PeopleCompositor, WalkersMoveAtTheirSpeedBackAndForth)
{
    sim::CompositedPerson p;
    p.start = {1, 2, 0};
    p.direction = {1, 0, 0};
    p.halfRange = 1.0;
    p.speed = 0.8;
    EXPECT_NEAR((p.feetAt(0.0) - Eigen::Vector3d(0, 2, 0)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((p.feetAt(0.5) - p.feetAt(0.0)).norm(), 0.4, 1e-9);
    EXPECT_NEAR(p.feetAt(2.5).x(), 2.0, 1e-9);  // far end after 2 m at 0.8 m/s
    EXPECT_NEAR(p.feetAt(5.0).x(), 0.0, 1e-9);  // back at the start after a period
    for (double t = 0; t < 10; t += 0.37)
        EXPECT_LE(std::abs(p.feetAt(t).x() - 1.0), 1.0 + 1e-9);
}
