#include <gtest/gtest.h>

#include <vector>

#include "smap/core/Median.h"

using smap::core::upperMedian;
using smap::core::upperMedianInPlace;

TEST(Median, UpperMedianOfOddEvenAndEmpty)
{
    EXPECT_EQ(upperMedian(std::vector<double>{5.0, 1.0, 3.0}), 3.0);
    EXPECT_EQ(upperMedian(std::vector<double>{4.0, 1.0, 3.0, 2.0}), 3.0);  // the upper one
    EXPECT_EQ(upperMedian(std::vector<int>{7}), 7);
    EXPECT_EQ(upperMedian(std::vector<double>{}), 0.0);
    EXPECT_EQ(upperMedian(std::vector<double>{}, -1.0), -1.0);
}

TEST(Median, InPlaceLeavesTheMedianAtTheMiddle)
{
    std::vector<float> v{9.f, 2.f, 7.f, 4.f, 1.f};
    const std::vector<float> copy = v;
    EXPECT_EQ(upperMedian(copy), 4.f);
    EXPECT_EQ(copy, (std::vector<float>{9.f, 2.f, 7.f, 4.f, 1.f}));  // the copy version
    EXPECT_EQ(upperMedianInPlace(v), 4.f);
    EXPECT_EQ(v[2], 4.f);
}
