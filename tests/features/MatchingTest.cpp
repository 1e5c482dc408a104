// Descriptor distance, ratio-test matching, the keypoint grid and the rotation consistency
// filter, on hand-made inputs with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/core.hpp>
#include <random>

#include "smap/features/DescriptorMatcher.h"
#include "smap/features/FeatureGrid.h"
#include "smap/features/RotationConsistency.h"

using namespace smap::features;

TEST(DescriptorDistance, CountsDifferingBits)
{
    uint8_t a[32] = {}, b[32] = {};
    EXPECT_EQ(descriptorDistance(a, b), 0);
    b[0] = 0xFF;
    b[31] = 0x01;
    b[17] = 0x30;
    EXPECT_EQ(descriptorDistance(a, b), 8 + 1 + 2);
    std::fill(std::begin(b), std::end(b), 0xFF);
    EXPECT_EQ(descriptorDistance(a, b), 256);
    // Random descriptors against OpenCV's Hamming norm.
    cv::Mat d(200, 32, CV_8UC1);
    cv::randu(d, 0, 256);
    for (int i = 0; i + 1 < d.rows; ++i)
        EXPECT_EQ(descriptorDistance(d.ptr<uint8_t>(i), d.ptr<uint8_t>(i + 1)),
                  static_cast<int>(cv::norm(d.row(i), d.row(i + 1), cv::NORM_HAMMING)))
            << i;
}

TEST(MatchWithRatioTest, FindsPlantedMatchesAndRejectsAmbiguousOnes)
{
    std::mt19937 rng(1);
    cv::Mat train(50, 32, CV_8UC1);
    cv::randu(train, 0, 256);
    cv::Mat query(3, 32, CV_8UC1);
    train.row(7).copyTo(query.row(0));
    query.at<uint8_t>(0, 3) ^= 0x0F;  // 4 bits off row 7
    train.row(20).copyTo(query.row(1));
    // Row 2 is ambiguous: equally close to rows 30 and 31.
    train.row(30).copyTo(train.row(31));
    train.row(30).copyTo(query.row(2));
    const auto m = matchWithRatioTest(query, train, 0.8F, 50);
    ASSERT_EQ(m.size(), 2U);
    EXPECT_EQ(m[0].query, 0U);
    EXPECT_EQ(m[0].train, 7U);
    EXPECT_EQ(m[0].distance, 4);
    EXPECT_EQ(m[1].query, 1U);
    EXPECT_EQ(m[1].train, 20U);
    // Restricting the train rows removes the match.
    EXPECT_TRUE(matchWithRatioTest(query.rowRange(0, 1), train, 0.8F, 50, {}, {1, 2, 3}).empty());
}

TEST(FeatureGrid, QueryReturnsExactlyThePointsInTheWindowAndLevels)
{
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> ux(0, 640), uy(0, 480);
    std::vector<cv::Point2f> pts;
    std::vector<int> levels;
    for (int i = 0; i < 2000; ++i)
    {
        pts.emplace_back(ux(rng), uy(rng));
        levels.push_back(i % 8);
    }
    pts.emplace_back(-3.0F, 500.0F);  // outside: lands in a border cell
    levels.push_back(0);
    const FeatureGrid grid(pts, levels, 640, 480);
    for (int q = 0; q < 50; ++q)
    {
        const float u = ux(rng), v = uy(rng), r = 5.0F + static_cast<float>(q);
        auto got = grid.query(u, v, r, 2, 5);
        std::sort(got.begin(), got.end());
        std::vector<size_t> want;
        for (size_t i = 0; i < pts.size(); ++i)
            if (std::abs(pts[i].x - u) <= r && std::abs(pts[i].y - v) <= r && levels[i] >= 2 &&
                levels[i] <= 5)
                want.push_back(i);
        EXPECT_EQ(got, want);
    }
    const auto corner = grid.query(0.0F, 479.0F, 25.0F);
    EXPECT_NE(std::find(corner.begin(), corner.end(), pts.size() - 1), corner.end());
}

TEST(RotationConsistency, RejectsMatchesOutsideTheDominantRotation)
{
    RotationConsistency rot;
    for (size_t i = 0; i < 40; ++i)
        rot.add(i, 10.0F, 40.0F + static_cast<float>(i % 3));  // about +30 degrees
    rot.add(100, 0.0F, 180.0F);
    rot.add(101, 350.0F, 100.0F);
    auto bad = rot.inconsistent();
    std::sort(bad.begin(), bad.end());
    EXPECT_EQ(bad, (std::vector<size_t>{100, 101}));
}
