// RunLog: the end-of-run diagnosis (silent when most frames are tracked, otherwise naming the
// likeliest cause read from the frames' own statistics) and frames.csv's columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "smap/apps/RunLog.h"

using namespace smap;

namespace
{
/// A log of `n` frames, `tracked` of them with a pose, all with the given statistics.
apps::RunLog makeLog(size_t n, size_t tracked, double validDepth, double medianDepth,
                     double intensity)
{
    apps::RunLog log;
    for (size_t i = 0; i < n; ++i)
    {
        pipeline::FrameStats s;
        s.index = i;
        s.validDepthFraction = validDepth;
        s.depthMedian = medianDepth;
        s.meanIntensity = intensity;
        pipeline::SemanticMapper::FrameResult r;
        r.tracking.frameId = i;
        r.tracking.status = i < tracked ? slam::TrackingStatus::Ok : slam::TrackingStatus::Lost;
        log.add(s, static_cast<double>(i) / 30.0, core::PinholeCamera{}, r);
    }
    return log;
}

bool mentions(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}
}  // namespace

TEST(RunLog, NoDiagnosisWhenMostFramesAreTracked)
{
    EXPECT_EQ(makeLog(10, 10, 0.9, 2.0, 120.0).trackingDiagnosis(0.1, 8.0), "");
    EXPECT_EQ(makeLog(10, 5, 0.9, 2.0, 120.0).trackingDiagnosis(0.1, 8.0), "");
    EXPECT_EQ(apps::RunLog().trackingDiagnosis(0.1, 8.0), "");
}

TEST(RunLog, DiagnosisNamesTheLikeliestCause)
{
    const std::string noDepth = makeLog(10, 0, 0.0, 0.0, 120.0).trackingDiagnosis(0.1, 8.0);
    EXPECT_TRUE(mentions(noDepth, "only 0 of 10 frames")) << noDepth;
    EXPECT_TRUE(mentions(noDepth, "no valid depth")) << noDepth;

    // TUM data read at 1000 units per metre: depths five times too far.
    const std::string scale = makeLog(10, 4, 0.8, 12.5, 120.0).trackingDiagnosis(0.1, 8.0);
    EXPECT_TRUE(mentions(scale, "only 4 of 10 frames")) << scale;
    EXPECT_TRUE(mentions(scale, "12.50 m")) << scale;
    EXPECT_TRUE(mentions(scale, "depth_factor")) << scale;

    const std::string black = makeLog(10, 0, 0.8, 2.0, 1.0).trackingDiagnosis(0.1, 8.0);
    EXPECT_TRUE(mentions(black, "black")) << black;

    const std::string texture = makeLog(10, 2, 0.8, 2.0, 120.0).trackingDiagnosis(0.1, 8.0);
    EXPECT_TRUE(mentions(texture, "texture")) << texture;
}

namespace
{
size_t fieldCount(const std::string& line)
{
    return static_cast<size_t>(std::count(line.begin(), line.end(), ',')) + 1;
}

std::vector<std::string> csvLines(const std::string& csv)
{
    std::vector<std::string> out;
    size_t start = 0;
    for (size_t end = csv.find('\n'); end != std::string::npos; end = csv.find('\n', start))
    {
        out.push_back(csv.substr(start, end - start));
        start = end + 1;
    }
    return out;
}
}  // namespace

TEST(RunLog, SkippedFramesHaveAsManyColumnsAsTheHeader)
{
    apps::RunLog log = makeLog(3, 3, 0.9, 2.0, 120.0);
    io::SkippedFrame skipped;
    skipped.index = 3;  // after the three frames read
    skipped.file = "rgb/1.png";
    skipped.reason = "missing";
    log.addSkipped(skipped);
    const auto lines = csvLines(log.framesCsv(true));
    ASSERT_EQ(lines.size(), 5u);
    EXPECT_NE(lines[0].find(",tracking_ms,map_wait_ms,tracking_cpu_ms,"), std::string::npos)
        << lines[0];
    EXPECT_NE(lines[4].find(",skipped,"), std::string::npos) << lines[4];
    EXPECT_NE(lines[4].find("rgb/1.png: missing"), std::string::npos) << lines[4];
    for (const auto& line : lines)
        EXPECT_EQ(fieldCount(line), fieldCount(lines[0])) << line;
}
