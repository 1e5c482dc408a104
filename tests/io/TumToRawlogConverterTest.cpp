#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <fstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/io/RangeImageFile.h"
#include "smap/io/RawlogSource.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumTextFormats.h"
#include "smap/io/TumToRawlogConverter.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
/// The TUM folder and the rawlog converted from it give `count` identical frames.
void expectSameFrames(const std::string& folder, const io::FrameSourceParameters& p,
                      const std::string& rawlogPath, size_t count)
{
    io::TumSource again(folder, p);
    io::RawlogSource rawlog(rawlogPath, {});
    size_t n = 0;
    while (auto a = again.next())
    {
        auto b = rawlog.next();
        ASSERT_TRUE(b.has_value());
        EXPECT_EQ(cv::norm(a->colour, b->colour, cv::NORM_INF), 0.0);
        EXPECT_EQ(cv::norm(a->depth, b->depth, cv::NORM_INF), 0.0);  // bit-identical metres
        EXPECT_EQ(a->camera, b->camera);
        EXPECT_NEAR(a->timestamp, b->timestamp, 1e-6);  // MRPT stores 100 ns ticks
        EXPECT_EQ(a->name, b->name);
        n++;
    }
    EXPECT_EQ(n, count);
    EXPECT_FALSE(rawlog.next().has_value());
}
}  // namespace

TEST(TumToRawlogConverter, RawlogReadsBackAsTheSameFrames)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 5, 0.004, false);
    io::FrameSourceParameters p;
    p.tum_depth_factor = 5000.0;
    p.camera = test::smallCamera();
    io::TumSource folder(dir / "tum", p);
    io::TumToRawlogConverter conv;
    const auto r = conv.convert(folder, p.tum_depth_factor, dir / "out.rawlog");
    EXPECT_EQ(r.frames, 5u);
    EXPECT_TRUE(fs::exists(dir / "out_Images/rgb/f0.png"));
    EXPECT_TRUE(fs::exists(dir / "out_Images/depth/f4.bin"));
    EXPECT_EQ(r.groundTruthPath, dir / "out_groundtruth.txt");
    EXPECT_EQ(io::readTumTrajectory(r.groundTruthPath).size(), 5u);
    // Only the finished outputs remain (no temporaries).
    size_t entries = static_cast<size_t>(
        std::distance(fs::directory_iterator(dir.str()), fs::directory_iterator()));
    EXPECT_EQ(entries, 4u);  // tum/, out.rawlog, out_Images/, out_groundtruth.txt

    expectSameFrames(dir / "tum", p, dir / "out.rawlog", 5);
}

TEST(TumToRawlogConverter, FailureLeavesNoPartialOutput)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 3, 0.0, false);
    fs::remove(dir / "tum/depth/f2.png");
    io::FrameSourceParameters p;
    p.camera = test::smallCamera();
    io::TumSource folder(dir / "tum", p);
    io::TumToRawlogConverter conv;
    EXPECT_THROW(conv.convert(folder, 5000.0, dir / "out.rawlog"), std::exception);
    EXPECT_FALSE(fs::exists(dir / "out.rawlog"));
    EXPECT_FALSE(fs::exists(dir / "out_Images"));
    size_t entries = static_cast<size_t>(
        std::distance(fs::directory_iterator(dir.str()), fs::directory_iterator()));
    EXPECT_EQ(entries, 1u);
}

TEST(TumToRawlogConverter, HolesWrittenAs65535BecomeMrptsZero)
{
    // MRPT's tools (RawLogViewer, rawlog-edit --generate-3d-pointclouds) take 0 as "no range";
    // 65535 (7-Scenes' hole value) would be a point 13 m away at 5000 units per metre.
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 1, 0.0, false);
    cv::Mat raw = test::patternDepthRaw(64, 48, 0);
    raw.at<uint16_t>(5, 6) = 65535;
    cv::imwrite(dir.str() + "/tum/depth/f0.png", raw);
    io::FrameSourceParameters p;
    p.tum_depth_factor = 5000.0;
    p.camera = test::smallCamera();
    io::TumSource folder(dir / "tum", p);
    io::TumToRawlogConverter conv;
    conv.convert(folder, p.tum_depth_factor, dir / "out.rawlog");
    const cv::Mat written = io::readExternalRangeImage(dir / "out_Images/depth/f0.bin");
    ASSERT_EQ(written.size(), raw.size());
    EXPECT_EQ(written.at<uint16_t>(5, 6), 0);
    EXPECT_EQ(written.at<uint16_t>(10, 20), raw.at<uint16_t>(10, 20));
    cv::Mat expected = raw.clone();
    expected.at<uint16_t>(5, 6) = 0;
    EXPECT_EQ(cv::norm(written, expected, cv::NORM_INF), 0.0);
}

TEST(TumToRawlogConverter, ImagesListedOutsideTheFolderAreCopiedIntoTheImagesFolder)
{
    // rgb.txt may name a file by an absolute path or through "../": the copy must land inside
    // OUT_Images, never on the source file or beside it.
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 3, 0.0, false);
    fs::create_directories(dir / "elsewhere");
    fs::rename(dir / "tum/rgb/f1.png", dir / "elsewhere/f1.png");
    fs::rename(dir / "tum/depth/f2.png", dir / "elsewhere/f2.png");
    {
        std::ofstream rgb(dir / "tum/rgb.txt"), depth(dir / "tum/depth.txt");
        rgb << std::fixed << 100.0 << " rgb/f0.png\n"
            << 100.0 + 1 / 30.0 << " " << (dir / "elsewhere/f1.png") << "\n"
            << 100.0 + 2 / 30.0 << " rgb/f2.png\n";
        depth << std::fixed << 100.0 << " depth/f0.png\n"
              << 100.0 + 1 / 30.0 << " depth/f1.png\n"
              << 100.0 + 2 / 30.0 << " ../elsewhere/f2.png\n";
    }
    const auto sourceBytes = fs::file_size(dir / "elsewhere/f1.png");
    io::FrameSourceParameters p;
    p.tum_depth_factor = 5000.0;
    p.camera = test::smallCamera();
    io::TumSource folder(dir / "tum", p);
    io::TumToRawlogConverter conv;
    EXPECT_EQ(conv.convert(folder, p.tum_depth_factor, dir / "out.rawlog").frames, 3U);
    EXPECT_TRUE(fs::exists(dir / "out_Images/outside/rgb/1/f1.png"));
    EXPECT_TRUE(fs::exists(dir / "out_Images/outside/depth/2/f2.bin"));
    EXPECT_EQ(fs::file_size(dir / "elsewhere/f1.png"), sourceBytes);
    EXPECT_FALSE(fs::exists(dir / "elsewhere/f2.bin"));

    expectSameFrames(dir / "tum", p, dir / "out.rawlog", 3);
}

TEST(TumToRawlogConverter, ColourImagesThatDoNotFitTheCameraAreRefused)
{
    // Colour files are copied, not decoded: without this check a rawlog whose intrinsics do not
    // fit its colour images would be written, and only fail when read.
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 2, 0.0, false);
    cv::imwrite(dir.str() + "/tum/rgb/f0.png", cv::Mat(24, 32, CV_8UC3, cv::Scalar(50, 90, 130)));
    io::FrameSourceParameters p;
    p.camera = test::smallCamera();
    io::TumSource folder(dir / "tum", p);
    io::TumToRawlogConverter conv;
    const std::string msg =
        test::inputErrorOf([&] { conv.convert(folder, 5000.0, dir / "out.rawlog"); });
    EXPECT_NE(msg.find("f0.png"), std::string::npos) << msg;
    EXPECT_NE(msg.find("32x24"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(dir / "out.rawlog"));
    EXPECT_FALSE(fs::exists(dir / "out_Images"));
}

TEST(TumToRawlogConverter, UnregisteredDepthKeepsBothCamerasAndReadsBackRegistered)
{
    // Depth at 80x60 from a camera 3 cm to the colour camera's left and turned by 2 degrees:
    // the rawlog stores the depth as recorded with both cameras and their extrinsic, and
    // reading it back (with no configuration at all) registers it exactly as the folder does.
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 3, 0.0, false);
    for (int i = 0; i < 3; i++)
        cv::imwrite(dir / ("tum/depth/f" + std::to_string(i) + ".png"),
                    test::patternDepthRaw(80, 60, i));
    io::FrameSourceParameters p;
    p.tum_depth_factor = 5000.0;
    p.camera = test::smallCamera();
    p.depth_camera = test::smallCamera(80, 60, 75.0);
    p.T_colour_depth.translation() = Eigen::Vector3d(-0.03, 0.0, 0.0);
    p.T_colour_depth.linear() =
        Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    io::TumSource folder(dir / "tum", p);
    io::TumToRawlogConverter conv;
    conv.convert(folder, p.tum_depth_factor, dir / "out.rawlog");

    mrpt::io::CFileGZInputStream in(dir / "out.rawlog");
    mrpt::serialization::CSerializable::Ptr entry;
    mrpt::serialization::archiveFrom(in) >> entry;
    const auto first = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(entry);
    ASSERT_TRUE(first);
    EXPECT_EQ(core::PinholeCamera::fromMrpt(first->cameraParams), *p.depth_camera);
    EXPECT_EQ(core::PinholeCamera::fromMrpt(first->cameraParamsIntensity), *p.camera);
    // MRPT's convention: the pose of the colour camera's optical frame in the depth sensor's
    // frame (x forward, y left, z up). The colour camera's origin in the depth camera's optical
    // frame (x right, y down, z forward) is o = -R^T t; in the sensor frame (o_z, -o_x, -o_y).
    const Eigen::Vector3d o = p.T_colour_depth.inverse().translation();
    const auto& rel = first->relativePoseIntensityWRTDepth;
    EXPECT_NEAR(rel.x(), o.z(), 1e-12);
    EXPECT_NEAR(rel.y(), -o.x(), 1e-12);
    EXPECT_NEAR(rel.z(), -o.y(), 1e-12);
    EXPECT_NEAR(o.x(), 0.03, 1e-4);  // the colour camera is to the depth camera's right

    expectSameFrames(dir / "tum", p, dir / "out.rawlog", 3);
}
