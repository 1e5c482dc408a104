// roundHalfAway against std::lround: at and just beside every half, and over random floats.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "smap/core/Rounding.h"

using smap::core::roundHalfAway;

TEST(RoundHalfAway, EqualsLroundAtAndBesideEveryHalf)
{
    for (int k = -40; k <= 40; ++k)
    {
        const float half = static_cast<float>(k) + 0.5F;
        for (const float v : {half, std::nextafter(half, -1e9F), std::nextafter(half, 1e9F),
                              static_cast<float>(k), std::nextafter(static_cast<float>(k), 1e9F),
                              std::nextafter(static_cast<float>(k), -1e9F)})
            EXPECT_EQ(roundHalfAway(v), std::lround(v)) << "v = " << v;
    }
    // 0.49999997f: adding 0.5 in float would round up to 1.
    EXPECT_EQ(roundHalfAway(std::nextafter(0.5F, 0.0F)), 0);
    EXPECT_EQ(roundHalfAway(-std::nextafter(0.5F, 0.0F)), 0);
    EXPECT_EQ(roundHalfAway(-0.0F), 0);
    EXPECT_EQ(roundHalfAway(-2.5F), -3);
    EXPECT_EQ(roundHalfAway(2.5F), 3);
}

TEST(RoundHalfAway, EqualsLroundOverRandomFloats)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(-1000.0F, 1000.0F);
    for (int i = 0; i < 200000; ++i)
    {
        const float v = value(rng);
        ASSERT_EQ(roundHalfAway(v), std::lround(v)) << "v = " << v;
    }
}
