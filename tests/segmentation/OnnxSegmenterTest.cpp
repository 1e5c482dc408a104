// The ESPNetv2 model through OnnxSegmenter: bit-for-bit against a direct cv::dnn pass, a person
// found where one was pasted, errors for bad models, use from a worker thread.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "TestData.h"
#include "smap/core/LabelSet.h"
#include "smap/segmentation/CrfSegmenter.h"
#include "smap/segmentation/OnnxSegmenter.h"

using namespace smap;
using segmentation::OnnxSegmenter;
using segmentation::OnnxSegmenterParameters;

namespace
{
std::string modelPath()
{
    return test::sharedDir() + "/models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx";
}

OnnxSegmenterParameters espnet()
{
    OnnxSegmenterParameters p;
    p.model = modelPath();
    return p;
}

core::RgbdFrame frameOf(const cv::Mat& bgr, const std::string& name)
{
    core::RgbdFrame f;
    f.colour = bgr;
    f.name = name;
    return f;
}

/// A 7-Scenes kitchen frame with a person cut-out pasted at (x, y), and the person's mask.
std::pair<cv::Mat, cv::Mat> kitchenWithPerson(int x, int y, double scale)
{
    cv::Mat bgr = cv::imread(test::sevenScenesDir() + "/rgb/frame-000100.jpg", cv::IMREAD_COLOR);
    cv::Mat person =
        cv::imread(test::sharedDir() + "/data/people/person_00.png", cv::IMREAD_UNCHANGED);
    cv::resize(person, person, cv::Size(), scale, scale, cv::INTER_AREA);
    cv::Mat mask(bgr.size(), CV_8UC1, cv::Scalar(0));
    for (int v = 0; v < person.rows; v++)
        for (int u = 0; u < person.cols; u++)
        {
            const auto& p = person.at<cv::Vec4b>(v, u);
            if (p[3] < 128 || y + v >= bgr.rows || x + u >= bgr.cols)
                continue;
            bgr.at<cv::Vec3b>(y + v, x + u) = {p[0], p[1], p[2]};
            mask.at<uint8_t>(y + v, x + u) = 255;
        }
    return {bgr, mask};
}

double iou(const cv::Mat& a, const cv::Mat& b)
{
    return static_cast<double>(cv::countNonZero(a & b)) / std::max(1, cv::countNonZero(a | b));
}
}  // namespace

TEST(OnnxSegmenter, MatchesADirectDnnForwardPassBitForBit)
{
    SMAP_REQUIRE_DATA(modelPath());
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    const cv::Mat bgr = cv::imread(test::sevenScenesDir() + "/rgb/frame-000000.jpg");
    ASSERT_FALSE(bgr.empty());
    OnnxSegmenter seg(espnet(), core::LabelSet::pascalVoc());
    const cv::Mat ours = seg.forward(bgr);

    // The model README's pre-processing, written out independently: RGB, / 255, ImageNet mean
    // and std, NCHW at 320x240.
    cv::Mat small, rgb, f;
    cv::resize(bgr, small, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    cv::cvtColor(small, rgb, cv::COLOR_BGR2RGB);
    rgb.convertTo(f, CV_32FC3, 1.0 / 255.0);
    f -= cv::Scalar(0.485, 0.456, 0.406);
    cv::divide(f, cv::Scalar(0.229, 0.224, 0.225), f);
    cv::dnn::Net net = cv::dnn::readNetFromONNX(modelPath());
    net.setInput(cv::dnn::blobFromImage(f));
    const cv::Mat direct = net.forward();

    ASSERT_EQ(ours.dims, 4);
    ASSERT_EQ(direct.dims, 4);
    for (int i = 0; i < 4; i++)
        EXPECT_EQ(ours.size[i], direct.size[i]);
    EXPECT_EQ(ours.size[1], 21);
    EXPECT_EQ(std::memcmp(ours.ptr<float>(), direct.ptr<float>(), ours.total() * sizeof(float)), 0);

    // Probabilities and labels follow from those scores: softmax and arg max.
    const auto r = seg.segmentNative(frameOf(bgr, "frame-000000"));
    ASSERT_EQ(r.width(), 320);
    ASSERT_EQ(r.height(), 240);
    int mismatches = 0;
    for (int i = 0; i < 320 * 240; i += 97)
    {
        int best = 0;
        for (int k = 1; k < 21; k++)
            if (direct.ptr<float>(0, k)[i] > direct.ptr<float>(0, best)[i])
                best = k;
        mismatches += r.labels.at<uint8_t>(i / 320, i % 320) != best;
    }
    EXPECT_EQ(mismatches, 0);
    const auto full = seg.segment(frameOf(bgr, "frame-000000"));
    EXPECT_EQ(full.width(), bgr.cols);
    EXPECT_EQ(full.height(), bgr.rows);
}

TEST(OnnxSegmenter, FindsAPastedPersonAndTheCrfKeepsIt)
{
    SMAP_REQUIRE_DATA(modelPath());
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    const auto [bgr, truth] = kitchenWithPerson(250, 120, 1.3);
    auto cnn = std::make_unique<OnnxSegmenter>(espnet(), core::LabelSet::pascalVoc());
    const auto plain = cnn->segment(frameOf(bgr, "pasted"));
    const double iouCnn = iou(plain.labels == 15, truth);
    EXPECT_GT(iouCnn, 0.6);
    segmentation::CrfSegmenter refined(std::move(cnn), segmentation::DenseCrfParameters());
    const auto r = refined.segment(frameOf(bgr, "pasted"));
    EXPECT_GT(iou(r.labels == 15, truth), iouCnn - 0.02);
}

TEST(OnnxSegmenter, UsableFromAWorkerThread)
{
    SMAP_REQUIRE_DATA(modelPath());
    SMAP_REQUIRE_DATA(test::sevenScenesDir());
    const cv::Mat bgr = cv::imread(test::sevenScenesDir() + "/rgb/frame-000050.jpg");
    OnnxSegmenter seg(espnet(), core::LabelSet::pascalVoc());
    const auto here = seg.segment(frameOf(bgr, "a"));
    segmentation::SegmentationResult there;
    std::thread worker([&] { there = seg.segment(frameOf(bgr, "a")); });
    worker.join();
    EXPECT_EQ(cv::countNonZero(here.labels != there.labels), 0);
}

TEST(OnnxSegmenter, BadModelsAreClearErrors)
{
    SMAP_REQUIRE_DATA(modelPath());
    test::TempDir dir;
    auto p = espnet();
    p.model = dir / "missing.onnx";
    EXPECT_NE(test::inputErrorOf([&] { OnnxSegmenter s(p, core::LabelSet::pascalVoc()); })
                  .find("missing.onnx"),
              std::string::npos);

    {
        std::ofstream f(dir / "garbage.onnx");
        f << "this is not a protobuf";
    }
    p.model = dir / "garbage.onnx";
    const std::string e =
        test::inputErrorOf([&] { OnnxSegmenter s(p, core::LabelSet::pascalVoc()); });
    EXPECT_NE(e.find("garbage.onnx"), std::string::npos) << e;

    // The class list must match the output: 20 names for a 21-class output.
    p = espnet();
    p.classes.pop_back();
    const std::string shape =
        test::inputErrorOf([&] { OnnxSegmenter s(p, core::LabelSet::pascalVoc()); });
    EXPECT_NE(shape.find("1x21x"), std::string::npos) << shape;
    EXPECT_NE(shape.find("20 classes"), std::string::npos) << shape;
    EXPECT_NE(shape.find("espnetv2_s2.0_voc_320x240.onnx"), std::string::npos) << shape;

    // A class the label set does not know, unless mapped.
    p = espnet();
    p.classes[18] = "couch";
    EXPECT_NE(
        test::inputErrorOf([&] { OnnxSegmenter s(p, core::LabelSet::pascalVoc()); }).find("couch"),
        std::string::npos);
    p.class_map = {{"couch", "sofa"}};
    EXPECT_EQ(test::inputErrorOf([&] { OnnxSegmenter s(p, core::LabelSet::pascalVoc()); }),
              "(no error)");
}

TEST(OnnxSegmenter, ClassMapSumsOntoTheLabelSet)
{
    SMAP_REQUIRE_DATA(modelPath());
    // Map every animal onto "background" and drop "aeroplane": columns still sum to one and
    // no pixel gets a dropped or merged-away label.
    auto p = espnet();
    for (const char* a : {"bird", "cat", "cow", "dog", "horse", "sheep"})
        p.class_map.emplace_back(a, "background");
    p.class_map.emplace_back("aeroplane", "void");
    OnnxSegmenter seg(p, core::LabelSet::pascalVoc());
    cv::Mat out(1, 4, CV_32FC1);
    int dims[4] = {1, 21, 1, 2};
    cv::Mat scores(4, dims, CV_32FC1, cv::Scalar(0.0f));
    scores.ptr<float>(0, 8)[0] = 5.0f;  // cat wins at pixel 0
    scores.ptr<float>(0, 1)[1] = 5.0f;  // aeroplane wins at pixel 1
    const cv::Mat probs = seg.toLabelProbabilities(scores);
    EXPECT_EQ(probs.rows, 21);
    EXPECT_EQ(probs.at<float>(8, 0), 0.0f);
    EXPECT_EQ(probs.at<float>(1, 1), 0.0f);
    EXPECT_GT(probs.at<float>(0, 0), 0.9f);
    cv::Mat sums;
    cv::reduce(probs, sums, 0, cv::REDUCE_SUM);
    EXPECT_NEAR(sums.at<float>(0), 1.0f, 1e-5);
    EXPECT_NEAR(sums.at<float>(1), 1.0f, 1e-5);
}
