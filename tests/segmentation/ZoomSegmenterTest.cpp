// The second look at people: where the crops go, and what a crop adds, with a stand-in network
// that, like a CNN at low resolution, misses what is thin in its input.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "TestData.h"
#include "smap/core/LabelSet.h"
#include "smap/segmentation/SegmentationParameters.h"
#include "smap/segmentation/ZoomSegmenter.h"

using namespace smap;
using segmentation::SegmentationResult;
using segmentation::ZoomParameters;
using segmentation::ZoomSegmenter;

namespace
{
constexpr int kPerson = 15;  // PASCAL VOC
constexpr int kTable = 11;   // diningtable: not movable
constexpr int kBackground = 0;

/// A stand-in network at a fixed working resolution: the frame shrunk to it (INTER_AREA), red
/// pixels are a person, and a morphological opening (3 x 3) removes what is thinner than three
/// of its pixels, as a network at low resolution loses thin parts. Counts its passes.
class ThinBlindSegmenter : public segmentation::Segmenter
{
public:
    ThinBlindSegmenter(int width, int height)
        : Segmenter("ThinBlind", core::LabelSet::pascalVoc()), width_(width), height_(height)
    {
    }
    SegmentationResult segmentNative(const core::RgbdFrame& frame) override
    {
        passes++;
        cv::Mat small;
        cv::resize(frame.colour, small, cv::Size(width_, height_), 0, 0, cv::INTER_AREA);
        cv::Mat red;
        cv::inRange(small, cv::Scalar(0, 0, 128), cv::Scalar(100, 100, 255), red);
        cv::morphologyEx(red, red, cv::MORPH_OPEN,
                         cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
        cv::Mat probabilities(static_cast<int>(labels().size()), width_ * height_, CV_32FC1,
                              cv::Scalar(0.0F));
        for (int v = 0; v < height_; ++v)
        {
            for (int u = 0; u < width_; ++u)
            {
                const bool person = red.at<uint8_t>(v, u) != 0;
                probabilities.at<float>(kPerson, v * width_ + u) = person ? 0.9F : 0.1F;
                probabilities.at<float>(kBackground, v * width_ + u) = person ? 0.1F : 0.9F;
            }
        }
        return SegmentationResult::fromProbabilities(probabilities, width_, height_);
    }
    std::string description() const override { return "thin-blind"; }
    int passes = 0;

private:
    int width_, height_;
};

/// 640 x 480: a person's torso (a red block) above a grey table top, and below the table the
/// legs, a red bar 19 px wide: 1.9 pixels of a 64 x 48 network, 3.8 on a crop of half the size.
core::RgbdFrame seatedPerson()
{
    core::RgbdFrame f;
    f.name = "seated";
    f.colour = cv::Mat(480, 640, CV_8UC3, cv::Scalar(40, 40, 40));
    f.colour(cv::Rect(260, 100, 120, 120)).setTo(cv::Scalar(0, 0, 255));
    f.colour(cv::Rect(150, 220, 340, 20)).setTo(cv::Scalar(128, 128, 128));
    f.colour(cv::Rect(300, 240, 19, 80)).setTo(cv::Scalar(0, 0, 255));
    return f;
}

cv::Mat labelsWithRegion(const cv::Rect& region, int label)
{
    cv::Mat l(60, 80, CV_8UC1, cv::Scalar(kBackground));
    l(region).setTo(label);
    return l;
}
}  // namespace

TEST(ZoomWindows, HalfTheFrameAroundTheLargestMovableRegionsFirst)
{
    const std::vector<bool> movable = core::LabelSet::pascalVoc().movable(0.5);
    cv::Mat labels =
        labelsWithRegion(cv::Rect(30, 10, 10, 20), kPerson);  // 200 px, centre (35, 20)
    labels(cv::Rect(70, 45, 6, 6)).setTo(kPerson);            // 36 px, centre (73, 48)
    labels(cv::Rect(2, 55, 2, 2)).setTo(kPerson);  // 4 px < 0.2 % of 4800: too small to look at
    const cv::Size frame(640, 480);                // 8 x the label grid
    const auto windows = segmentation::zoomWindows(labels, movable, frame, 4);
    ASSERT_EQ(windows.size(), 2U);
    EXPECT_EQ(windows[0], cv::Rect(120, 80, 320, 240))
        << "centred across on (280, 160), that centre a third of the way down";
    EXPECT_EQ(windows[1], cv::Rect(320, 240, 320, 240)) << "kept inside the frame";
    EXPECT_EQ(segmentation::zoomWindows(labels, movable, frame, 1).size(), 1U);
    EXPECT_TRUE(segmentation::zoomWindows(labels, movable, frame, 0).empty());
}

TEST(ZoomWindows, NoneForStaticClassesOrARegionAlreadyInAWindow)
{
    const std::vector<bool> movable = core::LabelSet::pascalVoc().movable(0.5);
    const cv::Size frame(640, 480);
    EXPECT_TRUE(segmentation::zoomWindows(labelsWithRegion(cv::Rect(30, 10, 10, 20), kTable),
                                          movable, frame, 2)
                    .empty())
        << "a table is not looked at again";
    cv::Mat labels = labelsWithRegion(cv::Rect(30, 10, 10, 20), kPerson);
    labels(cv::Rect(42, 24, 5, 5)).setTo(kPerson);  // centre (44.5, 26.5) -> (356, 212)
    EXPECT_EQ(segmentation::zoomWindows(labels, movable, frame, 2).size(), 1U)
        << "the second region's centre lies in the first window";
}

TEST(ZoomSegmenter, FindsWhatTheFirstPassMissesOnlyNearPeople)
{
    const core::RgbdFrame f = seatedPerson();
    ThinBlindSegmenter alone(64, 48);
    const SegmentationResult first = alone.segmentNative(f);
    // Network pixels (10 frame px each): the torso at (32, 16), the legs at (30.95, 28).
    ASSERT_EQ(first.labels.at<uint8_t>(16, 32), kPerson);
    ASSERT_EQ(first.labels.at<uint8_t>(28, 30), kBackground) << "the legs are too thin for it";

    auto inner = std::make_unique<ThinBlindSegmenter>(64, 48);
    ThinBlindSegmenter* network = inner.get();
    ZoomSegmenter zoom(std::move(inner), ZoomParameters{});
    const SegmentationResult r = zoom.segmentNative(f);
    EXPECT_EQ(network->passes, 2) << "the frame, then one crop around its one person";
    ASSERT_EQ(r.width(), 64);
    ASSERT_EQ(r.height(), 48);
    EXPECT_EQ(r.labels.at<uint8_t>(28, 30), kPerson) << "the crop sees the legs";
    EXPECT_EQ(r.labels.at<uint8_t>(16, 32), kPerson);
    EXPECT_EQ(r.labels.at<uint8_t>(5, 5), kBackground);
    EXPECT_EQ(r.labels.at<uint8_t>(28, 45), kBackground);
    cv::Mat sums;
    cv::reduce(r.probabilities, sums, 0, cv::REDUCE_SUM);
    double lo = 0.0, hi = 0.0;
    cv::minMaxLoc(sums, &lo, &hi);
    EXPECT_NEAR(lo, 1.0, 1e-4);
    EXPECT_NEAR(hi, 1.0, 1e-4);

    core::RgbdFrame empty = f;
    empty.colour.setTo(cv::Scalar(40, 40, 40));
    network->passes = 0;
    const SegmentationResult none = zoom.segmentNative(empty);
    EXPECT_EQ(network->passes, 1) << "no person, no second look";
    EXPECT_EQ(cv::countNonZero(none.labels != kBackground), 0);

    core::RgbdFrame small = f;
    cv::resize(f.colour, small.colour, cv::Size(100, 75), 0, 0, cv::INTER_AREA);
    network->passes = 0;
    zoom.segmentNative(small);
    EXPECT_EQ(network->passes, 1)
        << "100x75 is less than twice 64x48: a crop would only enlarge the same pixels";
}

TEST(ZoomSegmenter, ConfigKeysAreCheckedAndZeroLeavesItOut)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("segmentation", "zoom_crops", 9);
    segmentation::SegmentationParameters p;
    EXPECT_NE(test::inputErrorOf([&] { p.loadFromConfigFile(cfg, ""); }).find("zoom_crops = 9"),
              std::string::npos);
    mrpt::config::CConfigFileMemory prior;
    prior.write("segmentation", "zoom_min_prior", 1.5);
    segmentation::SegmentationParameters q;
    EXPECT_NE(test::inputErrorOf([&] { q.loadFromConfigFile(prior, ""); }).find("zoom_min_prior"),
              std::string::npos);
    mrpt::config::CConfigFileMemory off;
    off.write("segmentation", "zoom_crops", 0);
    segmentation::SegmentationParameters r;
    EXPECT_EQ(r.zoom.crops, 2) << "on by default";
    r.loadFromConfigFile(off, "");
    EXPECT_EQ(r.zoom.crops, 0);
}
