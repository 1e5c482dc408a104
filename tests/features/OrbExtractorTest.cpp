// ORB extraction: count and spread over the image, invariance to rotation and scale checked
// against the known warp, depth assignment.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "TestData.h"
#include "smap/features/DescriptorMatcher.h"
#include "smap/features/OrbExtractor.h"

using namespace smap;

namespace
{
// A textured test image: random blobs and lines of many sizes (corners at every scale).
cv::Mat texturedImage(int w, int h, uint32_t seed)
{
    cv::Mat img(h, w, CV_8UC1, cv::Scalar(128));
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> x(0, w - 1), y(0, h - 1), grey(0, 255), r(2, 40);
    for (int i = 0; i < 600; ++i)
    {
        const cv::Point c(x(rng), y(rng));
        if (i % 3 == 0)
            cv::rectangle(img, c, c + cv::Point(r(rng), r(rng)), cv::Scalar(grey(rng)), -1);
        else if (i % 3 == 1)
            cv::circle(img, c, r(rng), cv::Scalar(grey(rng)), -1);
        else
            cv::line(img, c, cv::Point(x(rng), y(rng)), cv::Scalar(grey(rng)), 2);
    }
    cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
    return img;
}
}  // namespace

TEST(OrbExtractor, ExtractsAboutTheRequestedNumberSpreadOverImageAndLevels)
{
    features::OrbParameters p;
    const features::OrbExtractor orb(p);
    const cv::Mat img = texturedImage(640, 480, 3);
    const auto fs = orb.extract(img);
    EXPECT_GE(fs.size(), 900U);
    EXPECT_LE(fs.size(), 1000U);
    EXPECT_EQ(fs.descriptors.rows, static_cast<int>(fs.size()));
    EXPECT_EQ(fs.descriptors.cols, 32);
    // Every cell of a 4x4 partition holds features, and every pyramid level is used.
    int cells[4][4] = {};
    std::vector<int> perLevel(8, 0);
    for (const auto& kp : fs.keypoints)
    {
        ASSERT_GE(kp.pt.x, 0.0F);
        ASSERT_LT(kp.pt.x, 640.0F);
        ASSERT_GE(kp.pt.y, 0.0F);
        ASSERT_LT(kp.pt.y, 480.0F);
        cells[static_cast<int>(kp.pt.y / 120)][static_cast<int>(kp.pt.x / 160)]++;
        perLevel[static_cast<size_t>(kp.octave)]++;
    }
    for (auto& row : cells)
        for (int c : row)
            EXPECT_GE(c, 20);
    for (size_t l = 0; l < perLevel.size(); ++l)
        EXPECT_GT(perLevel[l], 0) << "level " << l;
    // Level 0 gets the largest share: geometric series with factor 1 / 1.2.
    EXPECT_GT(perLevel[0], perLevel[7]);
}

// A `fill_last` region gets corners only once the rest of the image has none left to give:
// with the left half marked, a fully textured image fills the whole budget from the right
// half; a flat right half leaves the budget to the marked left half after all.
TEST(OrbExtractor, FillLastRegionsGetCornersOnlyAfterTheRest)
{
    const features::OrbExtractor orb{features::OrbParameters{}};
    const cv::Mat img = texturedImage(640, 480, 3);
    // The mask may have any size: 8 x 6 cells, left half set.
    cv::Mat leftHalf(6, 8, CV_8UC1, cv::Scalar(0));
    leftHalf.colRange(0, 4).setTo(255);
    auto countLeft = [](const features::FeatureSet& fs)
    {
        return std::count_if(fs.keypoints.begin(), fs.keypoints.end(),
                             [](const cv::KeyPoint& kp) { return kp.pt.x < 320.0F; });
    };
    const auto plain = orb.extract(img);
    const auto prioritised = orb.extract(img, leftHalf);
    EXPECT_GT(countLeft(plain), static_cast<long>(0.4 * static_cast<double>(plain.size())));
    EXPECT_EQ(countLeft(prioritised), 0) << "the right half has corners enough for the budget";
    EXPECT_GE(prioritised.size(), 900U) << "the budget is still filled";

    cv::Mat halfFlat = img.clone();
    halfFlat.colRange(320, 640).setTo(90);
    const auto fallback = orb.extract(halfFlat, leftHalf);
    EXPECT_GE(fallback.size(), 900U) << "marked corners fill what the rest cannot";
    EXPECT_EQ(countLeft(fallback), static_cast<long>(fallback.size()));
}

TEST(OrbExtractor, SameImageGivesIdenticalFeatures)
{
    const features::OrbExtractor orb{features::OrbParameters{}};
    const cv::Mat img = texturedImage(320, 240, 5);
    const auto a = orb.extract(img), b = orb.extract(img);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_HAMMING), 0.0);
}

TEST(OrbExtractor, FlatImageHasNoFeatures)
{
    const features::OrbExtractor orb{features::OrbParameters{}};
    EXPECT_EQ(orb.extract(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90))).size(), 0U);
}

// Rotating by 30 degrees and scaling by 1.3 about the centre: descriptor matches must land
// where the known similarity puts them, and orientations must turn by 30 degrees.
TEST(OrbExtractor, MatchesSurviveRotationAndScaleAtTheirTruePositions)
{
    const features::OrbExtractor orb{features::OrbParameters{}};
    const cv::Mat img = texturedImage(640, 480, 7);
    const cv::Point2f centre(320, 240);
    const double angle = 30.0, scale = 1.3;
    const cv::Mat A = cv::getRotationMatrix2D(centre, angle, scale);
    cv::Mat warped;
    cv::warpAffine(img, warped, A, img.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                   cv::Scalar(128));
    const auto a = orb.extract(img), b = orb.extract(warped);
    const auto matches = features::matchWithRatioTest(a.descriptors, b.descriptors, 0.8F, 64);
    int good = 0;
    std::vector<float> turn;
    for (const auto& m : matches)
    {
        const cv::Point2f p = a.keypoints[m.query].pt;
        const cv::Point2f q(static_cast<float>(A.at<double>(0, 0) * p.x + A.at<double>(0, 1) * p.y +
                                               A.at<double>(0, 2)),
                            static_cast<float>(A.at<double>(1, 0) * p.x + A.at<double>(1, 1) * p.y +
                                               A.at<double>(1, 2)));
        if (cv::norm(q - b.keypoints[m.train].pt) < 4.0 * scale)
        {
            good++;
            float d = a.keypoints[m.query].angle - b.keypoints[m.train].angle;
            d = std::fmod(d + 720.0F, 360.0F);
            turn.push_back(d);
        }
    }
    ASSERT_GE(matches.size(), 150U);
    EXPECT_GE(good, static_cast<int>(0.8 * static_cast<double>(matches.size())))
        << good << " of " << matches.size();
    // OpenCV's angle is counter-clockwise in image coordinates (y down): the keypoint angle
    // decreases by 30 degrees in the warped image, i.e. a - b = 30.
    std::sort(turn.begin(), turn.end());
    EXPECT_NEAR(turn[turn.size() / 2], angle, 4.0);
}

TEST(AssignDepth, DepthAndVirtualRightCoordinateAndEdgeRejection)
{
    features::FeatureSet fs;
    fs.keypoints = {cv::KeyPoint(20, 20, 31), cv::KeyPoint(50, 20, 31), cv::KeyPoint(70, 40, 31)};
    fs.undistorted = {fs.keypoints[0].pt, fs.keypoints[1].pt, fs.keypoints[2].pt};
    cv::Mat depth(60, 100, CV_32FC1, cv::Scalar(2.0F));
    depth(cv::Rect(51, 0, 49, 60)).setTo(4.0F);  // a step right next to keypoint 1
    depth.at<float>(40, 70) = 0.0F;              // keypoint 2 has no depth
    features::assignDepth(fs, depth, 40.0, 0.1, 8.0, 0.05);
    EXPECT_FLOAT_EQ(fs.depth[0], 2.0F);
    EXPECT_FLOAT_EQ(fs.rightU[0], 20.0F - 40.0F / 2.0F);
    EXPECT_EQ(fs.depth[1], 0.0F) << "depth on a discontinuity is not trusted";
    EXPECT_LT(fs.rightU[1], 0.0F);
    EXPECT_EQ(fs.depth[2], 0.0F);
    // With the edge test off the step pixel's own depth is used.
    features::assignDepth(fs, depth, 40.0, 0.1, 8.0, 1e9);
    EXPECT_FLOAT_EQ(fs.depth[1], 2.0F);
    // Out of range.
    features::assignDepth(fs, depth, 40.0, 0.1, 1.5, 1e9);
    EXPECT_EQ(fs.depth[0], 0.0F);
}

TEST(OrbParameters, InvalidValuesNameTheKey)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("orb", "scale_factor", 2.5);
    features::OrbParameters p;
    EXPECT_NE(test::inputErrorOf([&] { p.loadFromConfigFile(cfg, ""); }).find("scale_factor"),
              std::string::npos);
    mrpt::config::CConfigFileMemory cfg2;
    cfg2.write("orb", "fast_threshold", 5);
    cfg2.write("orb", "min_fast_threshold", 9);
    features::OrbParameters p2;
    EXPECT_NE(test::inputErrorOf([&] { p2.loadFromConfigFile(cfg2, ""); }).find("min_fast"),
              std::string::npos);
}
