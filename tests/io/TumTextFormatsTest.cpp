#include <gtest/gtest.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <sstream>

#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/io/TumTextFormats.h"

using namespace smap::io;

TEST(TumTextFormats, ParsesListsWithCommentsTabsAndCommas)
{
    std::istringstream in(
        "# comment\n\n1305031102.175304 rgb/a.png\n  "
        "1305031102.211214\trgb/b.png\r\n1.5,rgb/c.png\n");
    const auto l = parseTumList(in, "rgb.txt");
    ASSERT_EQ(l.size(), 3u);
    EXPECT_DOUBLE_EQ(l[0].timestamp, 1305031102.175304);
    EXPECT_EQ(l[1].file, "rgb/b.png");
    EXPECT_EQ(l[1].line, 4u);
    EXPECT_EQ(l[2].file, "rgb/c.png");
}

TEST(TumTextFormats, MalformedLinesNameFileAndLine)
{
    std::istringstream a("1.0 rgb/a.png\n2.0\n");
    EXPECT_NE(smap::test::inputErrorOf([&] { parseTumList(a, "rgb.txt"); }).find("rgb.txt:2:"),
              std::string::npos);
    std::istringstream b("1.0 a.png\nx.0 b.png\n");
    const std::string e = smap::test::inputErrorOf([&] { parseTumList(b, "depth.txt"); });
    EXPECT_NE(e.find("depth.txt:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("'x.0'"), std::string::npos) << e;
    std::istringstream c("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0\n");
    EXPECT_NE(smap::test::inputErrorOf([&] { parseTumTrajectory(c, "gt.txt"); }).find("gt.txt:2:"),
              std::string::npos);
    std::istringstream d("1 0 0 0 0 0 0 2\n");
    EXPECT_NE(
        smap::test::inputErrorOf([&] { parseTumTrajectory(d, "gt.txt"); }).find("quaternion norm"),
        std::string::npos);
    std::istringstream n("1 nan 0 0 0 0 0 1\n");
    EXPECT_NE(smap::test::inputErrorOf([&] { parseTumTrajectory(n, "gt.txt"); }).find("'nan'"),
              std::string::npos);
    std::istringstream as("1 a.png 2\n");
    EXPECT_NE(smap::test::inputErrorOf([&] { parseTumAssociations(as, "associations.txt"); })
                  .find("associations.txt:1:"),
              std::string::npos);
    EXPECT_NE(smap::test::inputErrorOf([] { readTumTrajectory("/nonexistent/gt.txt"); })
                  .find("/nonexistent/gt.txt"),
              std::string::npos);
}

TEST(TumTextFormats, TrajectoryRoundTripAtFullPrecision)
{
    std::istringstream in(
        "1305031102.1753045 1.5 -2.25 0.125 0.1 -0.2 0.3 0.9273618495495703\n"
        "1305031102.2 0.3333333333333333 0 0 0 0 0 -1\n");
    const auto t = parseTumTrajectory(in, "t");
    ASSERT_EQ(t.size(), 2u);
    EXPECT_DOUBLE_EQ(t[0].timestamp, 1305031102.1753045);
    EXPECT_DOUBLE_EQ(t[0].T_world_cam.x(), 1.5);

    smap::test::TempDir dir;
    writeTumTrajectory(dir / "t.txt", t, "test");
    const auto back = readTumTrajectory(dir / "t.txt");
    ASSERT_EQ(back.size(), t.size());
    for (size_t i = 0; i < t.size(); i++)
    {
        EXPECT_EQ(back[i].timestamp, t[i].timestamp);  // bit-exact
        EXPECT_EQ(back[i].T_world_cam.x(), t[i].T_world_cam.x());
        EXPECT_EQ(back[i].T_world_cam.y(), t[i].T_world_cam.y());
        EXPECT_NEAR((back[i].T_world_cam.getRotationMatrix() - t[i].T_world_cam.getRotationMatrix())
                        .asEigen()
                        .norm(),
                    0.0, 1e-15);
    }
    // qw is written non-negative: the second pose (qw = -1) comes out as identity, qw = +1.
    EXPECT_EQ(formatTumPose(back[1]).substr(formatTumPose(back[1]).size() - 2), " 1");
}

TEST(TumTextFormats, WrittenLinesLookLikeTumFiles)
{
    // Timestamps in plain decimals, as TUM's own files have them (never "1e+09", which
    // line-oriented tools and people misread), and no "-0" for a zero.
    smap::core::Trajectory t(1);
    t[0].timestamp = 1e9;
    t[0].T_world_cam = mrpt::poses::CPose3D(-0.0, 0.0, 1.5, 0.0, 0.0, 0.0);
    EXPECT_EQ(formatTumPose(t[0]), "1000000000 0 0 1.5 0 0 0 1");
    t[0].timestamp = 1305031102.175304;
    EXPECT_EQ(formatTumPose(t[0]).substr(0, 18), "1305031102.175304 ");
    t[0].timestamp = 0.25;
    EXPECT_EQ(formatTumPose(t[0]).substr(0, 5), "0.25 ");
}
