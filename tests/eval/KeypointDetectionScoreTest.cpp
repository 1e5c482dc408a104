#include <gtest/gtest.h>

#include "smap/eval/KeypointDetectionScore.h"

using smap::eval::KeypointDetectionScore;

namespace
{
KeypointDetectionScore withBand(size_t offBand, size_t onBand, size_t besideBand)
{
    KeypointDetectionScore s;
    s.maskOffBand = offBand;
    s.bandOnMask.keypoints = onBand;
    s.bandBesideMask.keypoints = besideBand;
    return s;
}
}  // namespace

TEST(KeypointDetectionScore, OutlineBoundSaysTheBandAtTheLeastRateThatReachesTheRecall)
{
    // 96 of 106 mask keypoints off the band: recall 0.95 needs 100.7, so 4.7 of the band's 10
    // on the mask (rate 0.47), and 4.7 of the 10 beside are said with them.
    EXPECT_NEAR(withBand(96, 10, 10).bestPrecisionAtRecall(0.95), 100.7 / 105.4, 1e-12);
    // Half the person on the band and as many beside: every band keypoint must be said for
    // recall 1, and then a third of what is said is beside.
    EXPECT_NEAR(withBand(20, 20, 20).bestPrecisionAtRecall(1.0), 40.0 / 60.0, 1e-12);
}

TEST(KeypointDetectionScore, OutlineBoundIsOneWhereTheBandIsNotNeeded)
{
    EXPECT_DOUBLE_EQ(withBand(100, 5, 50).bestPrecisionAtRecall(0.95), 1.0);
    EXPECT_DOUBLE_EQ(withBand(0, 0, 50).bestPrecisionAtRecall(0.95), 1.0);
    EXPECT_DOUBLE_EQ(KeypointDetectionScore().bestPrecisionAtRecall(0.95), 1.0);
}

TEST(KeypointDetectionScore, OutlineBoundAddsUpOverFrames)
{
    KeypointDetectionScore total = withBand(48, 5, 5);
    total += withBand(48, 5, 5);
    EXPECT_EQ(total.maskOffBand, 96U);
    EXPECT_NEAR(total.bestPrecisionAtRecall(0.95), 100.7 / 105.4, 1e-12);
}
