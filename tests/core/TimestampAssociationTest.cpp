#include <gtest/gtest.h>

#include "smap/core/TimestampAssociation.h"

using smap::core::associateTimestamps;

TEST(TimestampAssociation, ExactMatchesInOrder)
{
    const auto m = associateTimestamps({0.0, 1.0, 2.0}, {2.0, 0.0, 1.0}, 0.02);
    ASSERT_EQ(m.size(), 3u);
    EXPECT_EQ(m[0].first, 0u);
    EXPECT_EQ(m[0].second, 1u);
    EXPECT_EQ(m[1].second, 2u);
    EXPECT_EQ(m[2].second, 0u);
    for (const auto& p : m)
        EXPECT_EQ(p.dt, 0.0);
}

TEST(TimestampAssociation, GreedyBySmallestDifferenceIsOneToOne)
{
    // 1.000 is closest to both 1.005 and 0.990; the globally smallest |dt| (1.005, 0.005) wins,
    // leaving 0.990 for 0.991 though 0.991 alone would have preferred 1.000.
    const auto m = associateTimestamps({0.991, 1.005}, {0.990, 1.000}, 0.02);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0].first, 0u);
    EXPECT_EQ(m[0].second, 0u);
    EXPECT_EQ(m[1].first, 1u);
    EXPECT_EQ(m[1].second, 1u);
    EXPECT_NEAR(m[1].dt, 0.005, 1e-12);

    // Two candidates for one slot: only the closer is kept.
    const auto m2 = associateTimestamps({1.0}, {0.995, 1.003}, 0.02);
    ASSERT_EQ(m2.size(), 1u);
    EXPECT_EQ(m2[0].second, 1u);
}

TEST(TimestampAssociation, ToleranceIsStrict)
{
    EXPECT_EQ(associateTimestamps({10.0}, {10.019}, 0.02).size(), 1u);
    EXPECT_EQ(associateTimestamps({10.0}, {10.021}, 0.02).size(), 0u);
    EXPECT_EQ(associateTimestamps({0.0}, {0.5}, 0.5).size(), 0u);  // |dt| == max is rejected
}

TEST(TimestampAssociation, OffsetShiftsTheSecondList)
{
    const auto m = associateTimestamps({5.0, 6.0}, {4.0, 5.0}, 0.02, 1.0);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0].second, 0u);
    EXPECT_EQ(m[1].second, 1u);
}

TEST(TimestampAssociation, EmptyAndDisjointInputs)
{
    EXPECT_TRUE(associateTimestamps({}, {1.0}, 0.02).empty());
    EXPECT_TRUE(associateTimestamps({1.0}, {}, 0.02).empty());
    EXPECT_TRUE(associateTimestamps({1.0, 2.0}, {3.0, 4.0}, 0.02).empty());
}
