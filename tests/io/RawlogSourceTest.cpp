#include <gtest/gtest.h>
#include <mrpt/core/aligned_allocator.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/io/RawlogSource.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{

std::vector<core::RgbdFrame> readAll(const std::string& path,
                                     const io::FrameSourceParameters& p = {})
{
    io::RawlogSource src(path, p);
    std::vector<core::RgbdFrame> frames;
    while (auto f = src.next())
        frames.push_back(std::move(*f));
    return frames;
}

/// The frames of `path` that read() skipped.
std::vector<io::SkippedFrame> skippedOf(const std::string& path,
                                        const io::FrameSourceParameters& p = {})
{
    io::RawlogSource src(path, p);
    std::vector<io::SkippedFrame> skipped;
    while (auto r = src.read())
        if (const auto* s = std::get_if<io::SkippedFrame>(&*r))
            skipped.push_back(*s);
    return skipped;
}

mrpt::obs::CObservation3DRangeScan::Ptr sampleObservation(int seed,
                                                          const std::string& label = "KINECT")
{
    auto o =
        test::makeCoincidentObservation(test::smallCamera(), test::patternColour(64, 48, seed),
                                        test::patternDepthRaw(64, 48, seed), 0.0002f, 50.0 + seed);
    o->sensorLabel = label;
    return o;
}

void expectSameFrame(const core::RgbdFrame& a, const core::RgbdFrame& b)
{
    EXPECT_EQ(cv::norm(a.colour, b.colour, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
    EXPECT_EQ(a.camera, b.camera);
    EXPECT_DOUBLE_EQ(a.timestamp, b.timestamp);
}
}  // namespace

TEST(RawlogSource, ReadsMrptSampleWithColourIntrinsicsAndRegisteredDepth)
{
    SMAP_REQUIRE_DATA(test::mrptSampleRgbd());
    const auto frames = readAll(test::mrptSampleRgbd());
    ASSERT_EQ(frames.size(), 1u);
    const auto& f = frames[0];
    f.validate();
    // tests_rgbd.rawlog stores depth and colour cameras separately: the frame is expressed in
    // the colour (intensity) camera, whose calibration is fx 521.179, fy 493.033, c (322.516,
    // 259.056).
    EXPECT_EQ(f.camera.width, 640);
    EXPECT_EQ(f.camera.height, 480);
    EXPECT_NEAR(f.camera.fx, 521.17923, 1e-4);
    EXPECT_NEAR(f.camera.fy, 493.03303, 1e-4);
    EXPECT_NEAR(f.camera.cx, 322.51599, 1e-4);
    EXPECT_NEAR(f.camera.cy, 259.05597, 1e-4);
    EXPECT_NEAR(f.camera.distortion[0], 0.05858325, 1e-8);
    EXPECT_GT(f.validDepthFraction(), 0.6);

    // Independent check of the registration: MRPT's own unprojection of the range image (its
    // undistortion LUT, sensor frame x forward), moved into the colour camera and projected with
    // OpenCV, must agree with our depth at that pixel wherever that point is the visible one.
    mrpt::io::CFileGZInputStream in(test::mrptSampleRgbd());
    auto arch = mrpt::serialization::archiveFrom(in);
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(arch.ReadObject());
    ASSERT_TRUE(obs);
    mrpt::maps::CSimplePointsMap pts;
    obs->unprojectInto(pts);
    std::vector<cv::Point3d> inColour;
    for (size_t i = 0; i < pts.size(); i++)
    {
        float x, y, z;
        pts.getPoint(i, x, y, z);
        double cx, cy, cz;
        obs->relativePoseIntensityWRTDepth.inverseComposePoint(x, y, z, cx, cy, cz);
        if (cz > 0)
            inColour.emplace_back(cx, cy, cz);
    }
    ASSERT_GT(inColour.size(), 100000u);
    std::vector<cv::Point2d> px;
    cv::projectPoints(inColour, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), f.camera.cameraMatrix(),
                      f.camera.distCoeffs(), px);
    // Nearest projected point per colour pixel (the z-buffer), compared with our depth there.
    cv::Mat nearest(480, 640, CV_32FC1, cv::Scalar(0.0f));
    for (size_t i = 0; i < px.size(); i++)
    {
        const long u = std::lround(px[i].x), v = std::lround(px[i].y);
        if (u < 0 || v < 0 || u >= 640 || v >= 480)
            continue;
        float& z = nearest.at<float>(static_cast<int>(v), static_cast<int>(u));
        if (z == 0.0f || inColour[i].z < z)
            z = static_cast<float>(inColour[i].z);
    }
    size_t both = 0, agree = 0, onlyOne = 0;
    for (int v = 0; v < 480; v++)
        for (int u = 0; u < 640; u++)
        {
            const float a = nearest.at<float>(v, u), b = f.depth.at<float>(v, u);
            if ((a > 0) != (b > 0))
                onlyOne++;
            if (a > 0 && b > 0)
            {
                both++;
                agree += std::abs(a - b) < 1e-3f;
            }
        }
    EXPECT_GT(both, 200000u);
    EXPECT_GT(static_cast<double>(agree) / both, 0.999) << agree << " of " << both;
    EXPECT_EQ(onlyOne, 0u);
    RecordProperty("registration_agreement", std::to_string(static_cast<double>(agree) / both));
}

TEST(RawlogSource, BothLayoutsAndGzipGiveTheSameFrames)
{
    test::TempDir dir;
    const auto o0 = sampleObservation(0), o1 = sampleObservation(1);
    test::writeRawlog(dir / "obs.rawlog", {o0, o1});
    auto sf0 = mrpt::obs::CSensoryFrame::Create();
    sf0->insert(o0);
    auto sf1 = mrpt::obs::CSensoryFrame::Create();
    sf1->insert(std::make_shared<mrpt::obs::CObservationOdometry>());
    sf1->insert(o1);
    test::writeRawlog(
        dir / "sf.rawlog",
        {mrpt::obs::CActionCollection::Create(), sf0, mrpt::obs::CActionCollection::Create(), sf1},
        true);

    const auto a = readAll(dir / "obs.rawlog");
    const auto b = readAll(dir / "sf.rawlog");
    ASSERT_EQ(a.size(), 2u);
    ASSERT_EQ(b.size(), 2u);
    for (size_t i = 0; i < 2; i++)
        expectSameFrame(a[i], b[i]);
    // Known content: raw * rangeUnits (float product).
    const cv::Mat raw = test::patternDepthRaw(64, 48, 1);
    EXPECT_EQ(a[1].depth.at<float>(5, 7), static_cast<float>(raw.at<uint16_t>(5, 7)) * 0.0002f);
    EXPECT_EQ(cv::norm(a[1].colour, test::patternColour(64, 48, 1), cv::NORM_INF), 0.0);
    EXPECT_NEAR(a[1].timestamp, 51.0, 1e-6);
    EXPECT_EQ(a[1].camera, test::smallCamera());
}

TEST(RawlogSource, SaturatedRawDepthIsNoMeasurement)
{
    test::TempDir dir;
    cv::Mat raw = test::patternDepthRaw(64, 48, 0);
    raw.at<uint16_t>(5, 6) = 65535;
    raw.at<uint16_t>(7, 8) = 65534;
    const auto o = test::makeCoincidentObservation(
        test::smallCamera(), test::patternColour(64, 48, 0), raw, 0.001F, 1.0);
    test::writeRawlog(dir / "obs.rawlog", {o});
    const auto frames = readAll(dir / "obs.rawlog");
    ASSERT_EQ(frames.size(), 1U);
    EXPECT_EQ(frames[0].depth.at<float>(5, 6), 0.0F);
    EXPECT_NEAR(frames[0].depth.at<float>(7, 8), 65.534, 1e-3);
}

TEST(RawlogSource, FiltersBySensorLabel)
{
    test::TempDir dir;
    test::writeRawlog(dir / "two.rawlog", {sampleObservation(0, "A"), sampleObservation(1, "B"),
                                           sampleObservation(2, "A")});
    io::FrameSourceParameters p;
    p.rawlog_sensor_label = "B";
    const auto frames = readAll(dir / "two.rawlog", p);
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_NEAR(frames[0].timestamp, 51.0, 1e-6);
    p.rawlog_sensor_label = "C";
    const std::string e = smap::test::inputErrorOf([&] { readAll(dir / "two.rawlog", p); });
    EXPECT_NE(e.find("other than 'C'"), std::string::npos) << e;
}

TEST(RawlogSource, WithoutALabelOnlyTheFirstRgbdSensorIsRead)
{
    // Two cameras interleaved: reading both would make one camera jump between two places.
    test::TempDir dir;
    test::writeRawlog(dir / "two.rawlog",
                      {sampleObservation(0, "FRONT"), sampleObservation(1, "REAR"),
                       sampleObservation(2, "FRONT"), sampleObservation(3, "REAR")});
    const auto frames = readAll(dir / "two.rawlog");
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_NEAR(frames[0].timestamp, 50.0, 1e-6);
    EXPECT_NEAR(frames[1].timestamp, 52.0, 1e-6);
    io::FrameSourceParameters p;
    p.rawlog_sensor_label = "REAR";
    const auto rear = readAll(dir / "two.rawlog", p);
    ASSERT_EQ(rear.size(), 2u);
    EXPECT_NEAR(rear[0].timestamp, 51.0, 1e-6);
}

TEST(RawlogSource, RangeNotDepthIsConvertedAlongEachRay)
{
    // A plane at z = 1.5 m stored as Euclidean ranges (range_is_depth = false).
    const auto cam = test::smallCamera();
    cv::Mat raw(48, 64, CV_16UC1);
    const float units = 0.0001f;
    for (int v = 0; v < 48; v++)
        for (int u = 0; u < 64; u++)
        {
            const double x = (u - cam.cx) / cam.fx, y = (v - cam.cy) / cam.fy;
            raw.at<uint16_t>(v, u) =
                static_cast<uint16_t>(std::lround(1.5 * std::sqrt(1 + x * x + y * y) / units));
        }
    auto o = test::makeCoincidentObservation(cam, test::patternColour(64, 48, 0), raw, units, 1.0);
    o->range_is_depth = false;
    test::TempDir dir;
    test::writeRawlog(dir / "r.rawlog", {o});
    const auto f = readAll(dir / "r.rawlog");
    ASSERT_EQ(f.size(), 1u);
    double maxErr = 0;
    for (int v = 0; v < 48; v++)
        for (int u = 0; u < 64; u++)
            maxErr = std::max(maxErr, std::abs(f[0].depth.at<float>(v, u) - 1.5));
    EXPECT_LT(maxErr, 1e-4);  // half a range unit
    // Corner pixels differ most from their range: not converting would be off by ~2 cm there.
    EXPECT_GT(raw.at<uint16_t>(0, 0) * units - 1.5, 0.01);
}

TEST(RawlogSource, ExternallyStoredImagesResolveNextToTheRawlog)
{
    test::TempDir dir;
    const std::string imgDir = dir / "rec_Images";
    fs::create_directories(imgDir + "/rgb");
    fs::create_directories(imgDir + "/depth");
    auto embedded = sampleObservation(3);
    auto ext = sampleObservation(3);
    cv::imwrite(imgDir + "/rgb/c3.png", test::patternColour(64, 48, 3));
    ext->intensityImage.setExternalStorage("rgb/c3.png");
    ext->rangeImage_convertToExternalStorage("depth/d3.bin", imgDir + "/");
    test::writeRawlog(dir / "rec.rawlog", {ext});
    test::writeRawlog(dir / "emb.rawlog", {embedded});
    const auto a = readAll(dir / "rec.rawlog");
    const auto b = readAll(dir / "emb.rawlog");
    ASSERT_EQ(a.size(), 1u);
    expectSameFrame(a[0], b[0]);
    EXPECT_EQ(a[0].name, "c3");

    // MRPT's alternative folder names are found too.
    fs::rename(imgDir, dir / "rec_images");
    ASSERT_EQ(readAll(dir / "rec.rawlog").size(), 1u);
    fs::rename(dir / "rec_images", imgDir);

    // A missing external image costs its frame only: skipped, naming the image and why.
    fs::remove(imgDir + "/rgb/c3.png");
    EXPECT_TRUE(readAll(dir / "rec.rawlog").empty());
    const auto skipped = skippedOf(dir / "rec.rawlog");
    ASSERT_EQ(skipped.size(), 1u);
    EXPECT_EQ(skipped[0].index, 0u);
    EXPECT_NE(skipped[0].reason.find("rec_Images/rgb/c3.png' missing"), std::string::npos)
        << skipped[0].reason;
}

TEST(RawlogSource, RawlogWithoutRgbdSaysWhatItContains)
{
    test::TempDir dir;
    auto sf = mrpt::obs::CSensoryFrame::Create();
    sf->insert(mrpt::obs::CObservation2DRangeScan::Create());
    test::writeRawlog(dir / "laser.rawlog", {mrpt::obs::CActionCollection::Create(), sf});
    const std::string e = smap::test::inputErrorOf([&] { readAll(dir / "laser.rawlog"); });
    EXPECT_NE(e.find("no usable RGB-D observation"), std::string::npos) << e;
    EXPECT_NE(e.find("mrpt::obs::CObservation2DRangeScan x1"), std::string::npos) << e;
    EXPECT_NE(e.find("mrpt::obs::CActionCollection x1"), std::string::npos) << e;

    std::ofstream(dir / "empty.rawlog").close();
    EXPECT_NE(
        smap::test::inputErrorOf([&] { readAll(dir / "empty.rawlog"); }).find("contains: nothing"),
        std::string::npos);
    EXPECT_NE(
        smap::test::inputErrorOf([&] { readAll(dir / "missing.rawlog"); }).find("missing.rawlog"),
        std::string::npos);
}

TEST(RawlogSource, TruncatedRawlogEndsAfterTheGoodEntriesSayingWhere)
{
    test::TempDir dir;
    test::writeRawlog(dir / "t.rawlog",
                      {sampleObservation(0), sampleObservation(1), sampleObservation(2)});
    const auto size = fs::file_size(dir / "t.rawlog");
    fs::resize_file(dir / "t.rawlog", size * 5 / 6);
    io::RawlogSource src(dir / "t.rawlog", {});
    EXPECT_TRUE(src.next().has_value());
    EXPECT_TRUE(src.next().has_value());
    EXPECT_TRUE(src.endedEarly().empty());  // not before the damage is reached
    EXPECT_FALSE(src.read().has_value());   // an interrupted recording ends where it stops
    const std::string e = src.endedEarly();
    EXPECT_NE(e.find("entry 3"), std::string::npos) << e;
    EXPECT_NE(e.find("t.rawlog"), std::string::npos) << e;
    EXPECT_EQ(e.find("backtrace"), std::string::npos) << e;  // MRPT's root cause, not its dump
    EXPECT_FALSE(src.read().has_value());

    // Cut inside its first observation: nothing usable, an error naming the rawlog.
    fs::resize_file(dir / "t.rawlog", size / 6);
    const std::string first = smap::test::inputErrorOf([&] { readAll(dir / "t.rawlog"); });
    EXPECT_NE(first.find("t.rawlog"), std::string::npos) << first;
}

TEST(RawlogSource, TextFileIsNotARawlog)
{
    // A user passing a TUM list (or any other file) gets told what the file is not, in one line.
    test::TempDir dir;
    std::ofstream(dir / "associations.txt") << "100.0 rgb/f0.png 100.0 depth/f0.png\n";
    const std::string e =
        smap::test::inputErrorOf([&] { io::RawlogSource(dir / "associations.txt", {}).next(); });
    EXPECT_NE(e.find("associations.txt' is not an MRPT rawlog"), std::string::npos) << e;
    EXPECT_NE(e.find("TUM RGB-D folder"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(RawlogSource, CameraOverrideReplacesObservationIntrinsics)
{
    test::TempDir dir;
    test::writeRawlog(dir / "o.rawlog", {sampleObservation(0)});
    io::FrameSourceParameters p;
    p.camera = test::smallCamera(64, 48, 75.0);
    const auto f = readAll(dir / "o.rawlog", p);
    ASSERT_EQ(f.size(), 1u);
    EXPECT_EQ(f[0].camera.fx, 75.0);
    // A [camera] that does not fit the images: the frame is skipped, saying why.
    p.camera = test::smallCamera(640, 480);
    const auto skipped = skippedOf(dir / "o.rawlog", p);
    ASSERT_EQ(skipped.size(), 1u);
    EXPECT_NE(skipped[0].reason.find("[camera] says 640x480"), std::string::npos)
        << skipped[0].reason;
}

namespace
{
/// Reads the fuzz_rawlog seed `seed` to its end as `<name>.rawlog` (the sample's images folder
/// beside it): the early end it reports, the InputError's message, or "no error".
std::string outcomeOfFuzzSeed(const std::string& seed, const std::string& name)
{
    test::TempDir dir;
    const std::string rawlog = dir / (name + ".rawlog");
    fs::copy_file(test::sourceDir() + "/tests/fuzz/seeds/fuzz_rawlog/" + seed, rawlog);
    fs::create_directory_symlink(test::sourceDir() + "/rawlogs/sample_walking_xyz_Images",
                                 dir / (name + "_Images"));
    try
    {
        io::RawlogSource src(rawlog, {});
        while (src.read())
        {
        }
        const std::string ended = src.endedEarly();
        return ended.empty() ? "no error" : ended;
    }
    catch (const core::InputError& e)
    {
        return e.what();
    }
}
}  // namespace

TEST(RawlogSource, AbsurdSizesInADamagedRawlogAreDamageNotACrash)
{
    // MRPT 2.5 writes through the null pointer of a failed aligned allocation; ours throws.
    EXPECT_THROW(mrpt::aligned_malloc(std::size_t{1} << 62, 32), std::bad_alloc);
    void* small = mrpt::aligned_malloc(100, 32);
    ASSERT_NE(small, nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small) % 32, 0u);
    mrpt::aligned_free(small);

    // The fuzzer's find: a piece of the sample rawlog whose range image claims terabytes. It
    // crashed the reader (SIGSEGV in MRPT); now the rawlog ends there as damaged.
    const std::string outcome = outcomeOfFuzzSeed("regression-range-image-size", "found");
    EXPECT_NE(outcome.find("found.rawlog"), std::string::npos) << outcome;
}

TEST(RawlogSource, ADamagedJpegImageIsDamageNotTheEndOfTheProcess)
{
    // The fuzzer's find: a piece of the sample rawlog whose embedded JPEG image is damaged.
    // MRPT decodes it with libjpeg's default error handler, which called exit(); now the
    // rawlog ends there as damaged (JpegErrorGuard.cpp). Were exit() still called, this test
    // program would end here and the test fail.
    const std::string outcome = outcomeOfFuzzSeed("regression-damaged-jpeg", "jpeg");
    EXPECT_NE(outcome.find("jpeg.rawlog"), std::string::npos) << outcome;
    EXPECT_NE(outcome.find("CImage"), std::string::npos) << outcome;  // the damaged image
}
