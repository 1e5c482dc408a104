// Label images from disk: matched by name or timestamp, void pixels, errors naming the file.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "TestData.h"
#include "smap/core/LabelSet.h"
#include "smap/segmentation/CrfSegmenter.h"
#include "smap/segmentation/LabelImageSegmenter.h"
#include "smap/segmentation/SegmentationParameters.h"

using namespace smap;
using segmentation::LabelImageParameters;
using segmentation::LabelImageSegmenter;

namespace
{
core::RgbdFrame frame(const std::string& name, double t, int w = 8, int h = 6)
{
    core::RgbdFrame f;
    f.colour = cv::Mat(h, w, CV_8UC3, cv::Scalar::all(0));
    f.name = name;
    f.timestamp = t;
    return f;
}

cv::Mat labelImage(int first, int second)
{
    cv::Mat l(6, 8, CV_8UC1, cv::Scalar(first));
    l(cv::Rect(4, 0, 4, 6)).setTo(second);
    return l;
}
}  // namespace

TEST(LabelImageSegmenter, MatchesByNameWithConfidence)
{
    test::TempDir dir;
    cv::imwrite(dir / "000001.png", labelImage(15, 9));
    cv::Mat l = labelImage(0, 20);
    l.at<uint8_t>(0, 0) = 255;
    cv::imwrite(dir / "000002.png", l);
    LabelImageParameters p;
    p.folder = dir.str();
    LabelImageSegmenter seg(p, core::LabelSet::pascalVoc());
    const auto r = seg.segment(frame("000001", 0.0));
    EXPECT_EQ(r.labels.at<uint8_t>(3, 1), 15);
    EXPECT_EQ(r.labels.at<uint8_t>(3, 6), 9);
    EXPECT_FLOAT_EQ(r.probabilities.at<float>(15, 0), 0.9f);
    EXPECT_FLOAT_EQ(r.probabilities.at<float>(0, 0), 0.1f / 20.0f);

    const auto r2 = seg.segment(frame("000002", 0.0));
    EXPECT_EQ(r2.labels.at<uint8_t>(0, 0), 255);
    EXPECT_FLOAT_EQ(r2.probabilities.at<float>(7, 0), 1.0f / 21.0f);
    EXPECT_EQ(r2.labels.at<uint8_t>(5, 7), 20);

    // A frame of twice the size: probabilities resampled, labels from them.
    const auto big = seg.segment(frame("000001", 0.0, 16, 12));
    EXPECT_EQ(big.width(), 16);
    EXPECT_EQ(big.labels.at<uint8_t>(6, 2), 15);

    const std::string e = test::inputErrorOf([&] { seg.segment(frame("000003", 0.0)); });
    EXPECT_NE(e.find("000003"), std::string::npos) << e;
}

TEST(LabelImageSegmenter, VoidPixelsStayVoidThroughTheCrf)
{
    // A label image that only says where a person is (255 elsewhere, as a composite's labels
    // do): the CRF refines what the image says and leaves the rest void. Without that, the
    // void pixels' uniform distributions took the person's label from their neighbours, and
    // the semantic evidence then saw people over most of the view.
    test::TempDir dir;
    cv::Mat l(24, 32, CV_8UC1, cv::Scalar(core::LabelSet::kVoid));
    l(cv::Rect(12, 8, 8, 8)).setTo(15);
    cv::imwrite(dir / "000001.png", l);
    LabelImageParameters p;
    p.folder = dir.str();
    segmentation::CrfSegmenter seg(
        std::make_unique<LabelImageSegmenter>(p, core::LabelSet::pascalVoc()),
        segmentation::DenseCrfParameters());
    core::RgbdFrame f = frame("000001", 0.0, 32, 24);
    f.colour.setTo(cv::Scalar(90, 120, 150));
    f.colour(cv::Rect(12, 8, 8, 8)).setTo(cv::Scalar(20, 40, 200));
    const auto r = seg.segment(f);
    EXPECT_EQ(cv::countNonZero(r.labels == 15), 64);
    EXPECT_EQ(cv::countNonZero(r.labels == core::LabelSet::kVoid), 32 * 24 - 64);
}

TEST(LabelImageSegmenter, MatchesByNearestTimestamp)
{
    test::TempDir dir;
    cv::imwrite(dir / "1305031102.175304.png", labelImage(15, 15));
    cv::imwrite(dir / "1305031102.211214.png", labelImage(9, 9));
    LabelImageParameters p;
    p.folder = dir.str();
    p.match = "timestamp";
    LabelImageSegmenter seg(p, core::LabelSet::pascalVoc());
    EXPECT_EQ(seg.segment(frame("x", 1305031102.180)).labels.at<uint8_t>(0, 0), 15);
    EXPECT_EQ(seg.segment(frame("x", 1305031102.200)).labels.at<uint8_t>(0, 0), 9);
    EXPECT_NE(test::inputErrorOf([&] { seg.segment(frame("x", 1305031103.0)); }).find("no label"),
              std::string::npos);
}

TEST(LabelImageSegmenter, BadImagesAreErrorsNamingTheFile)
{
    test::TempDir dir;
    cv::imwrite(dir / "a.png", labelImage(0, 40));  // 40 is not a VOC id
    cv::imwrite(dir / "b.png", cv::Mat(6, 8, CV_8UC3, cv::Scalar::all(1)));
    cv::imwrite(dir / "c.png", cv::Mat(6, 6, CV_8UC1, cv::Scalar::all(1)));
    LabelImageParameters p;
    p.folder = dir.str();
    LabelImageSegmenter seg(p, core::LabelSet::pascalVoc());
    for (const char* name : {"a", "b", "c"})
    {
        const std::string e = test::inputErrorOf([&] { seg.segment(frame(name, 0.0)); });
        EXPECT_NE(e.find(std::string(name) + ".png"), std::string::npos) << e;
    }
    p.folder = dir / "nowhere";
    EXPECT_NE(test::inputErrorOf([&] { LabelImageSegmenter s(p, core::LabelSet::pascalVoc()); })
                  .find("nowhere"),
              std::string::npos);
}

TEST(LabelSet, MovableClassesByTheirDynamicPrior)
{
    const core::LabelSet voc = core::LabelSet::pascalVoc();
    const std::vector<bool> m = voc.movable(0.8);
    ASSERT_EQ(m.size(), 21U);
    for (size_t id = 0; id < m.size(); ++id)
        EXPECT_EQ(m[id], id == 15U) << voc[id].name;  // only person (0.9)
    EXPECT_TRUE(voc.movable(0.5)[7]) << "car, 0.5";
    EXPECT_FALSE(voc.movable(0.5)[9]) << "chair, 0.2";
}

TEST(LabelSet, ShippedVocTableEqualsTheBuiltInOne)
{
    const auto shipped = core::LabelSet::loadCsv(test::sourceDir() + "/config/labels/voc.csv");
    EXPECT_EQ(shipped.toCsv(), core::LabelSet::pascalVoc().toCsv());
    EXPECT_EQ(shipped.idOf("person"), 15);
    EXPECT_EQ(shipped.idOf("tvmonitor"), 20);
    EXPECT_EQ(shipped[15].colourBgr, cv::Vec3b(128, 128, 192));

    test::TempDir dir;
    {
        std::ofstream f(dir / "bad.csv");
        f << "id,name,r,g,b,dynamic_prior\n0,background,0,0,0,0\n2,person,1,2,3,0.9\n";
    }
    const std::string e = test::inputErrorOf([&] { core::LabelSet::loadCsv(dir / "bad.csv"); });
    EXPECT_NE(e.find("bad.csv"), std::string::npos) << e;
    EXPECT_NE(e.find("person"), std::string::npos) << e;
}

TEST(LabelImageSegmenter, ReadsMultiPageProbabilityImages)
{
    test::TempDir dir;
    // 21 pages of 16-bit p x 65535: person 0.7 on the left half, chair 0.6 on the right, the
    // rest shared; one 8-bit file with too few pages.
    std::vector<cv::Mat> pages;
    for (int k = 0; k < 21; k++)
    {
        cv::Mat page(6, 8, CV_16UC1, cv::Scalar(0));
        if (k == 15)
            page(cv::Rect(0, 0, 4, 6)).setTo(0.7 * 65535);
        else if (k == 9)
            page(cv::Rect(4, 0, 4, 6)).setTo(0.6 * 65535);
        else
            page.setTo(0.02 * 65535);
        pages.push_back(page);
    }
    ASSERT_TRUE(cv::imwritemulti(dir / "f0.tiff", pages));
    ASSERT_TRUE(cv::imwritemulti(dir / "f1.tiff",
                                 std::vector<cv::Mat>(3, cv::Mat(6, 8, CV_8UC1, cv::Scalar(9)))));
    LabelImageParameters p;
    p.folder = dir.str();
    p.kind = "probabilities";
    LabelImageSegmenter seg(p, core::LabelSet::pascalVoc());
    const auto r = seg.segment(frame("f0", 0.0));
    EXPECT_EQ(r.labels.at<uint8_t>(2, 1), 15);
    EXPECT_EQ(r.labels.at<uint8_t>(2, 6), 9);
    // Left: 0.7 + 19 x 0.02 + 0 (chair) = 1.08 before renormalising.
    EXPECT_NEAR(r.probabilities.at<float>(15, 1), 0.7f / 1.08f, 1e-4);
    cv::Mat sums;
    cv::reduce(r.probabilities, sums, 0, cv::REDUCE_SUM);
    EXPECT_LT(cv::norm(sums, cv::Mat::ones(1, 48, CV_32FC1), cv::NORM_INF), 1e-5);
    const std::string e = test::inputErrorOf([&] { seg.segment(frame("f1", 0.0)); });
    EXPECT_NE(e.find("f1.tiff"), std::string::npos) << e;
    EXPECT_NE(e.find("one page per class (21), not 3"), std::string::npos) << e;
}
