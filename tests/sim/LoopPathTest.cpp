// The corridor loop preset's camera path: a closed rounded rectangle walked at constant speed,
// with the camera looking along it; the corridor around it leaves room for the camera.
#include <gtest/gtest.h>

#include <cmath>

#include "smap/sim/CameraMotion.h"
#include "smap/sim/SequenceGenerator.h"
#include "smap/sim/SyntheticScene.h"

using namespace smap;

TEST(LoopPath, ClosedContinuousAndAsLongAsItsLength)
{
    sim::LoopPath p;
    p.min = {0.8, 0.8};
    p.max = {15.2, 9.2};
    p.cornerRadius = 0.6;
    // Walked in 1 mm steps, the points add up to the length, never jump, and the heading is
    // the direction of travel.
    const double L = p.length();
    EXPECT_NEAR(L, 2 * (14.4 + 8.4) - 8 * 0.6 + 2 * M_PI * 0.6, 1e-9);
    Eigen::Vector2d prev, h;
    p.at(0.0, prev, h);
    double walked = 0.0;
    for (double s = 0.001; s <= L + 1e-9; s += 0.001)
    {
        Eigen::Vector2d q;
        p.at(s, q, h);
        const double step = (q - prev).norm();
        ASSERT_LT(step, 0.00101) << "jump at s = " << s;
        EXPECT_NEAR(h.norm(), 1.0, 1e-9);
        if (step > 1e-6)
        {
            EXPECT_GT(h.dot((q - prev) / step), 0.999) << "heading off at s = " << s;
        }
        walked += step;
        prev = q;
    }
    EXPECT_NEAR(walked, L, 0.01);
    Eigen::Vector2d start, end;
    p.at(0.0, start, h);
    p.at(L, end, h);
    EXPECT_LT((start - end).norm(), 1e-9);
    // Starts in the middle of the lower edge heading +x; a quarter turn after each edge.
    EXPECT_LT((start - Eigen::Vector2d(8.0, 0.8)).norm(), 1e-9);
    p.at(0.5 * (14.4 - 1.2) + 0.5 * M_PI * 0.6 + 1.0, end, h);
    EXPECT_LT((end - Eigen::Vector2d(15.2, 1.4 + 1.0)).norm(), 1e-9);
    EXPECT_LT((h - Eigen::Vector2d(0, 1)).norm(), 1e-9);
}

TEST(LoopPath, CorridorPresetIsALapOfAtLeastThirtyMetresInsideTheCorridor)
{
    const sim::LoopPath p = sim::SyntheticScene::loopPath();
    EXPECT_GE(p.length(), 30.0);
    // The camera stays in the corridor: between the outer walls and the inner block, with
    // room for its sway.
    const sim::CameraMotion motion(p, 1);
    for (double t = 0.0; t < p.length() / p.speed; t += 0.05)
    {
        const auto T = motion.T_world_cam(t);
        const double x = T.x(), y = T.y();
        const bool inOuter = x > 0.3 && x < 15.7 && y > 0.3 && y < 9.7;
        const bool inBlock = x > 2.0 && x < 14.0 && y > 2.0 && y < 8.0;
        EXPECT_TRUE(inOuter && !inBlock) << "t = " << t << ": (" << x << ", " << y << ")";
        EXPECT_NEAR(T.z(), p.height, 0.06);
    }
    EXPECT_EQ(sim::findPreset("corridor_loop").scene, sim::SceneKind::CorridorLoop);
    EXPECT_EQ(sim::findPreset("static_corridor_loop").walking, 0);
}
