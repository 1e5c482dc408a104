#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/io/FrameSource.h"
#include "smap/io/TumSource.h"

using namespace smap;

namespace
{
io::FrameSourceParameters params(double factor = 5000.0)
{
    io::FrameSourceParameters p;
    p.tum_depth_factor = factor;
    p.camera = test::smallCamera();
    return p;
}
}  // namespace

TEST(TumSource, AssociatesListsAndConvertsDepth)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 4, 0.01, false);
    io::TumSource src(dir.str(), params(1000.0));
    EXPECT_EQ(src.sizeHint().value(), 4u);
    EXPECT_EQ(src.groundTruthPath(), dir / "groundtruth.txt");
    for (int i = 0; i < 4; i++)
    {
        auto f = src.next();
        ASSERT_TRUE(f.has_value());
        f->validate();
        EXPECT_EQ(f->index, static_cast<size_t>(i));
        EXPECT_NEAR(f->timestamp, 100.0 + i / 30.0, 1e-6);
        EXPECT_EQ(f->name, "f" + std::to_string(i));
        EXPECT_EQ(cv::norm(f->colour, test::patternColour(64, 48, i), cv::NORM_INF), 0.0);
        const cv::Mat raw = test::patternDepthRaw(64, 48, i);
        EXPECT_EQ(f->depth.at<float>(10, 20),
                  static_cast<float>(raw.at<uint16_t>(10, 20)) * static_cast<float>(1.0 / 1000.0));
        EXPECT_NEAR(f->depth.at<float>(10, 20), raw.at<uint16_t>(10, 20) / 1000.0, 1e-6);
        EXPECT_EQ(f->depth.at<float>(0, 17 - i), 0.0f);  // invalid raw 0 stays exactly 0
    }
    EXPECT_FALSE(src.next().has_value());
}

TEST(TumSource, SaturatedRawDepthIsNoMeasurement)
{
    // 7-Scenes writes 65535 for holes: it must read as 0 (invalid), not as 65.5 m, while the
    // value below it is still a (far) depth.
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 1, 0.0, false);
    cv::Mat raw = test::patternDepthRaw(64, 48, 0);
    raw.at<uint16_t>(5, 6) = 65535;
    raw.at<uint16_t>(7, 8) = 65534;
    cv::imwrite(dir.str() + "/depth/f0.png", raw);
    io::TumSource src(dir.str(), params(1000.0));
    const auto f = src.next();
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->depth.at<float>(5, 6), 0.0F);
    EXPECT_NEAR(f->depth.at<float>(7, 8), 65.534, 1e-3);
    EXPECT_NEAR(f->depth.at<float>(10, 20), raw.at<uint16_t>(10, 20) / 1000.0, 1e-6);
}

TEST(TumSource, UsesAssociationsFileAndSubsampling)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 6, 0.005, true);
    auto p = params();
    p.stride = 2;
    p.max_frames = 2;
    auto src = io::openFrameSource(dir.str(), p);
    EXPECT_EQ(src->sizeHint().value(), 2u);
    auto a = src->next();
    auto b = src->next();
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->index, 0u);
    EXPECT_EQ(b->index, 2u);
    EXPECT_FALSE(src->next().has_value());
}

TEST(TumSource, AssociationsWithDepthFirstAreReadRgbFirst)
{
    // associate.py depth.txt rgb.txt writes "t_depth depth/x.png t_rgb rgb/x.png".
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 3, 0.005, false);
    {
        std::ofstream assoc(dir / "associations.txt");
        for (int i = 0; i < 3; i++)
            assoc << std::fixed << 100.0 + i / 30.0 + 0.005 << " depth/f" << i << ".png "
                  << 100.0 + i / 30.0 << " rgb/f" << i << ".png\n";
    }
    io::TumSource src(dir.str(), params(1000.0));
    ASSERT_EQ(src.sizeHint().value(), 3u);
    for (int i = 0; i < 3; i++)
    {
        const auto f = src.next();
        ASSERT_TRUE(f.has_value());
        EXPECT_NEAR(f->timestamp, 100.0 + i / 30.0, 1e-6);
        EXPECT_EQ(cv::norm(f->colour, test::patternColour(64, 48, i), cv::NORM_INF), 0.0);
        EXPECT_NEAR(f->depth.at<float>(10, 20),
                    test::patternDepthRaw(64, 48, i).at<uint16_t>(10, 20) / 1000.0, 1e-6);
    }
}

TEST(TumSource, ReportsMissingImagesAndBadFolders)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 2, 0.0, false);
    std::filesystem::remove(dir / "rgb/f1.png");
    io::TumSource src(dir.str(), params());
    EXPECT_TRUE(src.next().has_value());
    try
    {
        src.next();
        FAIL();
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("rgb/f1.png"), std::string::npos) << e.what();
    }
    test::TempDir empty;
    EXPECT_THROW(io::TumSource(empty.str(), params()), core::InputError);
    EXPECT_THROW(io::openFrameSource(empty / "missing", params()), core::InputError);
}

TEST(TumSource, CameraSizeMismatchIsAnError)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 1, 0.0, false);
    auto p = params();
    p.camera = test::smallCamera(640, 480);
    io::TumSource src(dir.str(), p);
    EXPECT_THROW(src.next(), core::InputError);
}

TEST(TumSource, NoOverlappingTimestampsIsAnError)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 3, 0.5, false);  // depth 0.5 s late: nothing within 0.02 s
    try
    {
        io::TumSource src(dir.str(), params());
        FAIL();
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("no rgb/depth pairs"), std::string::npos);
    }
}

namespace
{
/// A room-scale view: depth rising from 0.8 m at the top to 4.0 m at the bottom, a few holes.
cv::Mat roomDepth(float scale)
{
    cv::Mat d(48, 64, CV_32FC1);
    for (int v = 0; v < d.rows; v++)
        for (int u = 0; u < d.cols; u++)
            d.at<float>(v, u) = (u % 13 == 0) ? 0.0F : scale * (0.8F + 3.2F * v / (d.rows - 1));
    return d;
}
}  // namespace

TEST(TumSource, DepthInTheRightUnitIsPlausible)
{
    EXPECT_FALSE(io::implausibleDepthScale(roomDepth(1.0F), 5000.0).has_value());
    EXPECT_FALSE(io::implausibleDepthScale(roomDepth(1.0F), 1000.0).has_value());
}

TEST(TumSource, MillimetresReadAsTumUnitsAreReported)
{
    // Millimetre PNGs read at 5000 units per metre: every depth 5x too small.
    const auto w = io::implausibleDepthScale(roomDepth(0.2F), 5000.0);
    ASSERT_TRUE(w.has_value());
    EXPECT_NE(w->find("depth 0.77 m"), std::string::npos) << *w;
    EXPECT_NE(w->find("depth_factor = 5000"), std::string::npos) << *w;
    EXPECT_NE(w->find("depth_factor = 1000"), std::string::npos) << *w;
}

TEST(TumSource, TumUnitsReadAsMillimetresAreReported)
{
    const auto w = io::implausibleDepthScale(roomDepth(5.0F), 1000.0);
    ASSERT_TRUE(w.has_value());
    EXPECT_NE(w->find("depth 19.32 m"), std::string::npos) << *w;
    EXPECT_NE(w->find("set [tum] depth_factor = 5000"), std::string::npos) << *w;
}

TEST(TumSource, TooLittleDepthIsNotJudged)
{
    cv::Mat d(48, 64, CV_32FC1, cv::Scalar(0.0F));
    d(cv::Rect(0, 0, 10, 10)).setTo(0.1F);  // 100 of 3072 pixels, all implausibly near
    EXPECT_FALSE(io::implausibleDepthScale(d, 5000.0).has_value());
    d(cv::Rect(0, 0, 20, 20)).setTo(0.1F);  // 400: now judged
    EXPECT_TRUE(io::implausibleDepthScale(d, 5000.0).has_value());
}

namespace
{
/// Reads every frame of `folder` at `depthFactor`; returns the warnings logged meanwhile.
std::vector<std::string> warningsReading(const std::string& folder, double depthFactor)
{
    io::TumSource src(folder, params(depthFactor));
    src.logging_enable_console_output = false;
    std::vector<std::string> warnings;
    src.logRegisterCallback(
        [&](std::string_view msg, mrpt::system::VerbosityLevel level, std::string_view,
            mrpt::Clock::time_point)
        {
            if (level == mrpt::system::LVL_WARN)
                warnings.emplace_back(msg);
        });
    while (src.next())
    {
    }
    return warnings;
}
}  // namespace

TEST(TumSource, WarnsOnceNamingTheDepthImageWhenTheUnitLooksWrong)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 3, 0.0, false);           // raw 5000-8000: 5-8 m in millimetres
    const auto warnings = warningsReading(dir.str(), 250.0);  // read 4x too far: 20-32 m
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(dir.str() + "/depth/f0.png"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("depth_factor = 250"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("check [tum] depth_factor"), std::string::npos) << warnings[0];
    EXPECT_TRUE(warningsReading(dir.str(), 1000.0).empty());
}
