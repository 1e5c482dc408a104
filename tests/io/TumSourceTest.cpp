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

namespace
{
/// What read() gave for every entry: "frame" or the skipped frame's reason.
std::vector<std::string> outcomes(io::FrameSource& src)
{
    std::vector<std::string> out;
    while (auto r = src.read())
    {
        if (const auto* s = std::get_if<io::SkippedFrame>(&*r))
            out.push_back(s->file + ": " + s->reason);
        else
            out.emplace_back("frame");
    }
    return out;
}

bool contains(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}
}  // namespace

TEST(TumSource, AnImageOfAnotherFormatIsSkippedNotDecoded)
{
    // Found by fuzz_tum_frame: a "PNG" whose bytes look like DICOM made OpenCV hand it to GDCM,
    // which aborts the process on it. Only the formats a recording holds are decoded.
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 2, 0.0, false);
    std::string dicom(128, '\0');
    dicom += "DICM";
    dicom += std::string(64, '\xff');
    std::ofstream(dir / "rgb/f1.png", std::ios::binary) << dicom;
    io::TumSource src(dir.str(), params());
    const auto got = outcomes(src);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0], "frame");
    EXPECT_TRUE(contains(got[1], "rgb/f1.png: colour image is not a PNG, JPEG, PNM, TIFF or BMP"))
        << got[1];
}

TEST(TumSource, BadImagesAreSkippedFramesNamingTheFileAndWhy)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 8, 0.0, false);
    std::filesystem::remove(dir / "rgb/f1.png");  // missing
    std::filesystem::resize_file(dir / "depth/f2.png",
                                 std::filesystem::file_size(dir / "depth/f2.png") / 2);  // cut
    std::ofstream(dir / "rgb/f3.png").close();                                           // 0 bytes
    cv::imwrite(dir / "depth/f4.png", test::patternDepthRaw(32, 24, 4));          // wrong size
    cv::imwrite(dir / "depth/f5.png", cv::Mat(48, 64, CV_16UC1, cv::Scalar(0)));  // no depth
    cv::imwrite(dir / "depth/f6.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(9)));   // 8-bit
    std::ofstream(dir / "rgb/f7.png") << "not a png at all";                      // garbage
    io::TumSource src(dir.str(), params());
    const auto got = outcomes(src);
    ASSERT_EQ(got.size(), 8u);
    EXPECT_EQ(got[0], "frame");
    EXPECT_TRUE(contains(got[1], "rgb/f1.png: colour image missing")) << got[1];
    EXPECT_TRUE(contains(got[2], "depth/f2.png: depth image cannot be decoded")) << got[2];
    EXPECT_TRUE(contains(got[3], "rgb/f3.png: colour image empty (0 bytes)")) << got[3];
    EXPECT_TRUE(contains(got[4], "depth/f4.png: depth image is 32x24, expected 64x48")) << got[4];
    EXPECT_TRUE(contains(got[5], "depth/f5.png: depth image holds no valid depth")) << got[5];
    EXPECT_TRUE(contains(got[6], "depth/f6.png: depth image is not a 16-bit")) << got[6];
    EXPECT_TRUE(contains(got[7], "rgb/f7.png: colour image is not a PNG, JPEG")) << got[7];

    // next() passes over them; the skipped frames keep their place in the indices.
    io::TumSource again(dir.str(), params());
    const auto first = again.next();
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->index, 0u);
    EXPECT_FALSE(again.next().has_value());
}

TEST(TumSource, CameraSizeMismatchSkipsTheFrameSayingSo)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 1, 0.0, false);
    auto p = params();
    p.camera = test::smallCamera(640, 480);
    io::TumSource src(dir.str(), p);
    const auto got = outcomes(src);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_TRUE(contains(got[0], "colour image is 64x48, expected 640x480")) << got[0];
}

TEST(TumSource, MalformedListLinesAreLeftOutAndEmptyListsNamed)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 3, 0.0, true);
    {
        std::ofstream assoc(dir / "associations.txt", std::ios::app);
        assoc << "garbage line here\n";
    }
    io::TumSource src(dir.str(), params());
    EXPECT_EQ(src.sizeHint().value(), 3u);
    EXPECT_EQ(src.badListLines(), 1u);
    EXPECT_EQ(outcomes(src), std::vector<std::string>(3, "frame"));

    // An empty list is an error naming that list, not the folder alone.
    std::ofstream(dir / "associations.txt").close();
    const std::string e = test::inputErrorOf([&] { io::TumSource(dir.str(), params()); });
    EXPECT_TRUE(contains(e, dir / "associations.txt") && contains(e, "lists no frames")) << e;
    std::filesystem::remove(dir / "associations.txt");
    std::ofstream(dir / "depth.txt") << "# only a comment\n";
    const std::string d = test::inputErrorOf([&] { io::TumSource(dir.str(), params()); });
    EXPECT_TRUE(contains(d, dir / "depth.txt") && contains(d, "lists no images")) << d;

    test::TempDir empty;
    EXPECT_TRUE(contains(test::inputErrorOf([&] { io::TumSource(empty.str(), params()); }),
                         "is not a TUM RGB-D folder"));
    EXPECT_THROW(io::openFrameSource(empty / "missing", params()), core::InputError);
}

TEST(TumSource, NoOverlappingTimestampsIsAnError)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 3, 0.5, false);  // depth 0.5 s late: nothing within 0.02 s
    const std::string e = test::inputErrorOf([&] { io::TumSource(dir.str(), params()); });
    EXPECT_TRUE(contains(e, "no timestamp of rgb.txt (3 images) has one in depth.txt")) << e;
    EXPECT_TRUE(contains(e, "max_dt = 0.02")) << e;
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

TEST(TumSource, DepthCameraPutsDepthOnTheColourGrid)
{
    // Depth camera 80x60 at f = 75, c = (39.5, 29.5); colour camera 64x48 at f = 60,
    // c = (31.5, 23.5), 5 cm to the depth camera's right (t_colour_depth = -0.05 along x). A wall
    // 2 m away: depth column u_d lands on colour column
    // 60 * ((u_d - 39.5) / 75 * 2 - 0.05) / 2 + 31.5 = 0.8 u_d - 1.6, row v_d on 0.8 v_d - 0.1.
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 1, 0.0, false);
    const cv::Mat wall(60, 80, CV_16UC1, cv::Scalar(2000));
    cv::imwrite(dir.str() + "/depth/f0.png", wall);
    auto p = params(1000.0);
    p.depth_camera = test::smallCamera(80, 60, 75.0);
    p.T_colour_depth.translation() = Eigen::Vector3d(-0.05, 0, 0);
    io::TumSource src(dir.str(), p);
    EXPECT_EQ(src.depthCamera(), *p.depth_camera);
    const auto f = src.next();
    ASSERT_TRUE(f.has_value());
    f->validate();
    EXPECT_EQ(f->camera, *p.camera);
    ASSERT_EQ(f->depth.size(), cv::Size(64, 48));
    // Columns: u_d = 2 -> 0.0 is the first, u_d = 79 -> 61.6 -> 62 the last; column 63 (the
    // colour camera sees further right) has no depth. Rows -0.1 .. 47.1: all reached.
    EXPECT_EQ(f->depth.at<float>(24, 0), 2.0F);
    EXPECT_EQ(f->depth.at<float>(24, 40), 2.0F);
    EXPECT_EQ(f->depth.at<float>(24, 62), 2.0F);
    EXPECT_EQ(f->depth.at<float>(24, 63), 0.0F);
    EXPECT_EQ(cv::countNonZero(f->depth), 63 * 48);
    // The colour camera 5 cm to the depth camera's LEFT: u_c = 0.8 u_d + 1.4, so column 0 has
    // no depth and column 63 has (u_d = 77 -> 63.0).
    auto left = p;
    left.T_colour_depth.translation() = Eigen::Vector3d(0.05, 0, 0);
    io::TumSource src2(dir.str(), left);
    const auto g = src2.next();
    ASSERT_TRUE(g.has_value());
    EXPECT_EQ(g->depth.at<float>(24, 0), 0.0F);
    EXPECT_EQ(g->depth.at<float>(24, 1), 2.0F);
    EXPECT_EQ(g->depth.at<float>(24, 63), 2.0F);
    EXPECT_EQ(cv::countNonZero(g->depth), 63 * 48);
}

TEST(TumSource, DepthImagesAreCheckedAgainstTheDepthCamerasSize)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 1, 0.0, false);  // 64x48 depth
    auto p = params(1000.0);
    p.depth_camera = test::smallCamera(80, 60, 75.0);
    io::TumSource src(dir.str(), p);
    const auto r = src.read();
    ASSERT_TRUE(r.has_value());
    const auto* skipped = std::get_if<io::SkippedFrame>(&*r);
    ASSERT_NE(skipped, nullptr);
    EXPECT_NE(skipped->reason.find("[depth_camera]"), std::string::npos) << skipped->reason;
}

TEST(TumSource, DepthCameraWithoutAColourCameraIsAnErrorNamingBoth)
{
    test::TempDir dir;
    test::writeTumFolder(dir.str(), 1, 0.0, false);
    io::FrameSourceParameters p;
    p.depth_camera = test::smallCamera();
    try
    {
        io::TumSource src(dir.str(), p);
        FAIL() << "no error";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("[depth_camera] needs a [camera]"), std::string::npos)
            << e.what();
    }
}
