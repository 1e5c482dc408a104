// Table III frame scores and IoU on hand-made label images with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "smap/eval/SegmentationScore.h"

using namespace smap;

namespace
{
cv::Mat blank(uint8_t label = 0)
{
    return cv::Mat(100, 100, CV_8UC1, cv::Scalar(label));
}
}  // namespace

TEST(SegmentationScore, FrameCountsFollowTheIouRule)
{
    eval::SegmentationScore score({{15, "person"}, {9, "chair"}});
    // Frame 1: person 20x20 true; predicted shifted by 5 px: IoU = 300 / 500 = 0.6 -> TP.
    cv::Mat gt = blank(), pr = blank();
    gt(cv::Rect(10, 10, 20, 20)).setTo(15);
    pr(cv::Rect(15, 10, 20, 20)).setTo(15);
    score.addFrame(gt, pr);
    // Frame 2: shifted by 10 px: IoU = 200 / 600 = 0.33 -> FN; a chair predicted where none
    // is -> chair FP.
    pr = blank();
    pr(cv::Rect(20, 10, 20, 20)).setTo(15);
    pr(cv::Rect(60, 60, 10, 10)).setTo(9);
    score.addFrame(gt, pr);
    // Frame 3: nobody, nothing predicted -> TN for both; a 3-pixel chair speck stays below
    // the minimum area (0.1% of 10000 = 10 px) -> still TN.
    pr = blank();
    pr(cv::Rect(0, 0, 3, 1)).setTo(9);
    score.addFrame(blank(), pr);

    ASSERT_EQ(score.frames(), 3u);
    const auto& person = score.classes()[0];
    EXPECT_EQ(person.tp, 1u);
    EXPECT_EQ(person.fn, 1u);
    EXPECT_EQ(person.fp, 0u);
    EXPECT_EQ(person.tn, 1u);
    EXPECT_DOUBLE_EQ(person.recall(), 0.5);
    EXPECT_DOUBLE_EQ(person.fnr(), 0.5);
    EXPECT_DOUBLE_EQ(person.precision(), 1.0);
    EXPECT_DOUBLE_EQ(person.fpr(), 0.0);
    EXPECT_DOUBLE_EQ(person.pwc(), 1.0 / 3.0);
    // Pixel IoU over all frames: (300 + 200) / (500 + 600).
    EXPECT_DOUBLE_EQ(person.iou(), 500.0 / 1100.0);

    const auto& chair = score.classes()[1];
    EXPECT_EQ(chair.tp + chair.fn, 0u);
    EXPECT_EQ(chair.fp, 1u);
    EXPECT_EQ(chair.tn, 2u);
    EXPECT_DOUBLE_EQ(chair.fpr(), 1.0 / 3.0);
    EXPECT_TRUE(std::isnan(chair.recall()));
    EXPECT_NE(score.toText().find("IoU >= 0.50"), std::string::npos);
}

TEST(SegmentationScore, VoidPixelsAreLeftOutAndBandIouLooksAtEdges)
{
    eval::SegmentationScoreOptions o;
    o.bandRadius = 2;
    eval::SegmentationScore score({{15, "person"}}, o);
    cv::Mat gt = blank(255), pr = blank();
    gt(cv::Rect(20, 20, 40, 40)).setTo(15);
    pr(cv::Rect(20, 20, 40, 40)).setTo(15);
    pr(cv::Rect(0, 0, 10, 10)).setTo(15);  // on void: not counted
    score.addFrame(gt, pr);
    const auto& c = score.classes()[0];
    EXPECT_EQ(c.tp, 1u);
    EXPECT_DOUBLE_EQ(c.iou(), 1.0);
    EXPECT_DOUBLE_EQ(c.bandIou(), 1.0);

    // The same prediction scored with every pixel: the void square counts against it.
    o.voidLabel = -1;
    eval::SegmentationScore all({{15, "person"}}, o);
    all.addFrame(gt, pr);
    EXPECT_DOUBLE_EQ(all.classes()[0].iou(), 1600.0 / 1700.0);

    // A prediction one pixel too big all round keeps a high IoU but loses band IoU.
    eval::SegmentationScore edge({{15, "person"}}, o);
    cv::Mat big = blank();
    big(cv::Rect(19, 19, 42, 42)).setTo(15);
    edge.addFrame(gt, big);
    EXPECT_GT(edge.classes()[0].iou(), 0.9);
    EXPECT_LT(edge.classes()[0].bandIou(), 0.8);
    EXPECT_THROW(edge.addFrame(gt, cv::Mat(10, 10, CV_8UC1)), std::invalid_argument);
}
