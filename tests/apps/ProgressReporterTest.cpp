// ProgressReporter: the progress line's figures, and the in-place terminal line.
#include <gtest/gtest.h>

#include <sstream>

#include "smap/apps/ProgressReporter.h"

using smap::apps::ProgressReporter;

TEST(ProgressReporter, LineShowsFramesRateAndEta)
{
    // 120 of 1000 frames in 4 s: 30 frames/s, 880 frames left -> ETA 29 s (rounded).
    EXPECT_EQ(ProgressReporter::line(120, 1000, 4.0), "frame 120 / 1000  30.0 frames/s  ETA 29 s");
    // Unknown total (a streamed rawlog): no ETA.
    EXPECT_EQ(ProgressReporter::line(50, std::nullopt, 2.0), "frame 50  25.0 frames/s");
    // Nothing done yet: no rate, no ETA.
    EXPECT_EQ(ProgressReporter::line(0, 10, 0.0), "frame 0 / 10  0.0 frames/s  ETA ?");
}

TEST(ProgressReporter, TerminalLineIsRewrittenInPlaceAndCleared)
{
    std::ostringstream term;
    mrpt::system::COutputLogger log("test");
    ProgressReporter p(10, &term, log);
    p.update(1, "1 keyframes, 0 lost");
    const std::string first = term.str();
    ASSERT_FALSE(first.empty());
    EXPECT_EQ(first[0], '\r');
    EXPECT_NE(first.find("frame 1 / 10"), std::string::npos) << first;
    EXPECT_NE(first.find("(1 keyframes, 0 lost)"), std::string::npos) << first;
    EXPECT_EQ(first.find('\n'), std::string::npos) << "never a new line on a terminal";
    p.finish();
    EXPECT_EQ(term.str().back(), '\r') << "the line is blanked at the end";
}
