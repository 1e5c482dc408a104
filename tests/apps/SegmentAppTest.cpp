// smap-segment and smap-eval segmentation from the command line: label images per frame named
// after the colour files, overlays, errors; the shipped ESPNetv2 configuration on real frames.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/apps/EvalApp.h"
#include "smap/apps/SegmentApp.h"
#include "smap/core/DataDirectory.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
/// A label image per frame of a writeTumFolder folder: person on the left half, chair on the
/// right half from frame 2 on.
void writeLabels(const std::string& dir, int frames)
{
    fs::create_directories(dir);
    for (int i = 0; i < frames; i++)
    {
        cv::Mat l(48, 64, CV_8UC1, cv::Scalar(0));
        l(cv::Rect(0, 0, 32, 48)).setTo(15);
        if (i >= 2)
            l(cv::Rect(32, 0, 32, 48)).setTo(9);
        cv::imwrite(dir + "/f" + std::to_string(i) + ".png", l);
    }
}

/// writeTumFolder's 64x48 camera.
std::string writeCameraConfig(const test::TempDir& dir)
{
    std::ofstream(dir / "camera.ini") << "[camera]\nwidth = 64\nheight = 48\nfx = 60\nfy = 60\n"
                                         "cx = 31.5\ncy = 23.5\nk1 = 0\nk2 = 0\np1 = 0\np2 = 0\n"
                                         "k3 = 0\n";
    return dir / "camera.ini";
}

int runSegment(const std::vector<std::string>& args, std::string* out = nullptr)
{
    apps::SegmentApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    std::ostringstream os;
    const int rc = app.run(args, os);
    if (out)
        *out = os.str();
    return rc;
}
}  // namespace

TEST(SegmentApp, WritesALabelImageAndOverlayPerFrame)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "seq", 4, 0.0, false);
    writeLabels(dir / "truth", 4);
    // Label images as the segmenter, without the CRF: the output must equal the input.
    std::string text;
    const std::string camera = writeCameraConfig(dir);
    ASSERT_EQ(runSegment({"--config", camera, dir / "seq", dir / "out", "--set",
                          "segmentation.backend=label_images", "--set",
                          "label_images.folder=" + (dir / "truth"), "--set", "crf.enabled=false"},
                         &text),
              0);
    EXPECT_NE(text.find("4 frames"), std::string::npos) << text;
    for (int i = 0; i < 4; i++)
    {
        const std::string name = "f" + std::to_string(i) + ".png";
        const cv::Mat got = cv::imread(dir / ("out/" + name), cv::IMREAD_UNCHANGED);
        const cv::Mat want = cv::imread(dir / ("truth/" + name), cv::IMREAD_UNCHANGED);
        ASSERT_EQ(got.type(), CV_8UC1) << name;
        EXPECT_EQ(cv::countNonZero(got != want), 0) << name;
        EXPECT_TRUE(fs::exists(dir / ("out/overlay/" + name))) << name;
    }
    EXPECT_TRUE(fs::exists(dir / "out/segmentation.json"));

    // Every 2nd frame, through the CRF: frames f0 and f2 only.
    ASSERT_EQ(runSegment({"--config", camera, dir / "seq", dir / "every2", "--every", "2",
                          "--no-overlay", "--set", "segmentation.backend=label_images", "--set",
                          "label_images.folder=" + (dir / "truth")}),
              0);
    EXPECT_TRUE(fs::exists(dir / "every2/f0.png"));
    EXPECT_FALSE(fs::exists(dir / "every2/f1.png"));
    EXPECT_TRUE(fs::exists(dir / "every2/f2.png"));
    EXPECT_FALSE(fs::exists(dir / "every2/overlay"));

    // smap-eval segmentation scores the first output against the truth: perfect.
    apps::EvalApp eval;
    std::ostringstream os;
    ASSERT_EQ(eval.run({"segmentation", dir / "truth", dir / "out", "--classes", "person,chair",
                        "--json", dir / "scores.json"},
                       os),
              0);
    EXPECT_NE(os.str().find("person             4     4     0     0     0"), std::string::npos)
        << os.str();
    EXPECT_NE(os.str().find("chair              2     2     0     0     2"), std::string::npos)
        << os.str();
    EXPECT_NE(test::readTextFile(dir / "scores.json").find("\"recall\": 1"), std::string::npos);
}

TEST(SegmentApp, BadInputIsAClearError)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "seq", 2, 0.0, false);
    // The default backend uses the shipped model; where the data folder lacks it (a broken
    // installation), that is the error.
    ::setenv(core::kDataDirectoryVariable, (dir / "empty-data-folder").c_str(), 1);
    const std::string noModel = test::inputErrorOf([&] { runSegment({dir / "seq", dir / "out"}); });
    ::unsetenv(core::kDataDirectoryVariable);
    EXPECT_NE(noModel.find("[onnx] model"), std::string::npos) << noModel;
    EXPECT_NE(noModel.find("empty-data-folder/models/espnetv2-voc/"), std::string::npos) << noModel;
    EXPECT_NE(test::inputErrorOf(
                  [&] {
                      runSegment(
                          {dir / "seq", dir / "out", "--set", "onnx.model=" + (dir / "none.onnx")});
                  })
                  .find("none.onnx"),
              std::string::npos);
    EXPECT_NE(test::inputErrorOf(
                  [&] {
                      runSegment({dir / "seq", dir / "out", "--set", "crf.colour=1"});
                  })
                  .find("colour"),
              std::string::npos);
    // A frame without a label image names the frame.
    writeLabels(dir / "truth", 1);
    EXPECT_NE(test::inputErrorOf(
                  [&]
                  {
                      runSegment({"--config", writeCameraConfig(dir), dir / "seq", dir / "out",
                                  "--set", "segmentation.backend=label_images", "--set",
                                  "label_images.folder=" + (dir / "truth")});
                  })
                  .find("'f1'"),
              std::string::npos);
    apps::EvalApp eval;
    std::ostringstream os;
    EXPECT_NE(test::inputErrorOf(
                  [&] {
                      eval.run({"segmentation", dir / "truth", dir / "seq"}, os);
                  })
                  .find("no label images"),
              std::string::npos);
}

TEST(SegmentApp, ShippedEspnetConfigurationOnRealFrames)
{
    const std::string model =
        test::sharedDir() + "/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx";
    SMAP_REQUIRE_DATA(model);
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    test::TempDir dir;
    std::string text;
    ASSERT_EQ(runSegment({"--config", test::sourceDir() + "/config/7scenes.ini", "--config",
                          test::sourceDir() + "/config/espnetv2_voc.ini", test::sevenScenesDir(),
                          dir / "out", "--max-frames", "2", "--set", "onnx.model=" + model},
                         &text),
              0);
    // Named after the colour files (frame-000000.jpg ...), full resolution, VOC ids; the
    // kitchen's dining table is what this model finds best there (model README).
    const cv::Mat l = cv::imread(dir / "out/frame-000000.png", cv::IMREAD_UNCHANGED);
    ASSERT_EQ(l.type(), CV_8UC1);
    EXPECT_EQ(l.cols, 640);
    EXPECT_EQ(l.rows, 480);
    double lo = 0, hi = 0;
    cv::minMaxLoc(l, &lo, &hi);
    EXPECT_LE(hi, 20.0);
    EXPECT_GT(cv::countNonZero(l == 11), 0) << "no dining table found";
    EXPECT_TRUE(fs::exists(dir / "out/overlay/frame-000001.png"));
    EXPECT_NE(text.find("dense CRF"), std::string::npos) << text;
}
