#include "smap/apps/RunLog.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <set>
#include <string_view>

#include "smap/core/Median.h"

namespace smap::apps
{
using core::upperMedian;

core::JsonValue timingJson(const std::vector<double>& milliseconds)
{
    double sum = 0.0;
    for (const double x : milliseconds)
        sum += x;
    auto j = core::JsonValue::object();
    j.set("median_ms", upperMedian(milliseconds)).set("total_s", sum / 1000.0);
    j.set("count", static_cast<uint64_t>(milliseconds.size()));
    return j;
}

void RunLog::add(const pipeline::FrameStats& stats, double timestamp,
                 const core::PinholeCamera& camera,
                 const pipeline::SemanticMapper::FrameResult& result)
{
    if (rows_.empty())
    {
        firstStamp_ = timestamp;
        camera_ = camera;
    }
    lastStamp_ = timestamp;
    const auto status = result.tracking.status;
    withPose_ += slam::hasPose(status) ? 1 : 0;
    lost_ += status == slam::TrackingStatus::Lost ? 1 : 0;
    relocalised_ += status == slam::TrackingStatus::Relocalised ? 1 : 0;
    reanchored_ += status == slam::TrackingStatus::Reanchored ? 1 : 0;
    sumValidDepth_ += stats.validDepthFraction;
    if (const auto earlier = result.tracking.posedEarlierFrameId)
    {
        for (auto& row : rows_)
        {
            auto& t = row.result.tracking;
            if (t.frameId == *earlier && !slam::hasPose(t.status))
            {
                t.status = slam::TrackingStatus::Odometry;
                withPose_++;
            }
        }
    }
    rows_.push_back({stats, result});
}

void RunLog::markDiscarded(const std::vector<uint64_t>& frameIds)
{
    const std::set<uint64_t> ids(frameIds.begin(), frameIds.end());
    for (auto& row : rows_)
    {
        auto& t = row.result.tracking;
        if (!ids.count(t.frameId) || !slam::hasPose(t.status))
            continue;
        t.status = slam::TrackingStatus::Discarded;
        withPose_--;
        discarded_++;
    }
}

std::string RunLog::trackingDiagnosis(double minDepth, double maxDepth) const
{
    const size_t n = rows_.size();
    if (n == 0 || 2 * withPose_ >= n)
        return {};
    std::vector<double> medians, intensities;
    for (const auto& row : rows_)
    {
        if (row.stats.validDepthFraction > 0.0)
            medians.push_back(row.stats.depthMedian);
        intensities.push_back(row.stats.meanIntensity);
    }
    const double validDepth = sumValidDepth_ / static_cast<double>(n);
    std::string why;
    if (validDepth < 0.05)
        why = mrpt::format(
            "the depth images hold almost no valid depth (%.1f %% of the pixels on average): "
            "check the depth files",
            100.0 * validDepth);
    else if (const double z = upperMedian(medians); z < minDepth || z > maxDepth)
        why = mrpt::format(
            "the median depth is %.2f m, outside the tracker's %.2f - %.2f m: check the depth "
            "scale ([tum] depth_factor: TUM 5000, 7-Scenes 1000 units per metre)",
            z, minDepth, maxDepth);
    else if (upperMedian(intensities) < 5.0)
        why = "the colour images are (nearly) black";
    else
        why =
            "too little texture or too fast a motion; frames.csv has keypoints and inliers per "
            "frame";
    return mrpt::format("only %zu of %zu frames have a pose: %s", withPose_, n, why.c_str());
}

namespace
{
/// A CSV field in double quotes (inner quotes doubled), so that commas in paths survive.
std::string quoted(const std::string& text)
{
    std::string q = "\"";
    for (const char c : text)
        q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

/// frames.csv's columns after the frame statistics.
constexpr std::string_view kTrackingColumns =
    "status,keypoints,inliers,keyframe,extraction_ms,matching_ms,optimisation_ms,tracking_ms,"
    "map_wait_ms,tracking_cpu_ms,dynamic_keypoints,dynamic_filter_ms,keyframe_queue_wait_ms,"
    "movable_keypoints,mask_age,mask_wait_ms,semantic_ms,fallback,note";

std::string skippedCsvRow(const io::SkippedFrame& s)
{
    pipeline::FrameStats stats;
    stats.index = s.index;
    stats.timestamp = s.timestamp;
    stats.name = s.name;
    // Every column after the status empty (nothing was measured) but the note, the last.
    const auto after = std::count(kTrackingColumns.begin(), kTrackingColumns.end(), ',');
    return pipeline::toCsvRow(stats) + ",skipped" + std::string(after, ',') +
           quoted(s.file + ": " + s.reason) + "\n";
}
}  // namespace

void RunLog::addSkipped(const io::SkippedFrame& frame)
{
    skipped_.push_back(frame);
}

namespace
{
/// movable_keypoints, mask_age (empty: no mask), mask_wait_ms, semantic_ms and the fallback the
/// tracker took (empty: none).
std::string semanticCsv(const pipeline::SemanticMapper::FrameResult& r, bool timings)
{
    return std::to_string(r.movableKeypoints) + "," +
           (r.maskAge ? std::to_string(*r.maskAge) : std::string()) + "," +
           (timings ? mrpt::format("%.3f,%.3f,", r.mask_wait_ms, r.semantic_ms) : ",,") +
           slam::toString(r.tracking.fallback);
}
}  // namespace

std::string RunLog::framesCsv(bool timings) const
{
    std::string csv = pipeline::frameStatsCsvHeader() + "," + std::string(kTrackingColumns) + "\n";
    auto nextSkipped = skipped_.begin();
    for (const auto& r : rows_)
    {
        for (; nextSkipped != skipped_.end() && nextSkipped->index < r.stats.index; ++nextSkipped)
            csv += skippedCsvRow(*nextSkipped);
        const auto& t = r.result.tracking;
        csv += pipeline::toCsvRow(r.stats) + "," + slam::toString(t.status) + "," +
               std::to_string(t.keypoints) + "," + std::to_string(t.inliers) + "," +
               (t.newKeyFrame ? "1" : "0") + "," +
               (timings ? mrpt::format("%.3f,%.3f,%.3f,%.3f,%.3f,%.3f", t.timings.extraction_ms,
                                       t.timings.matching_ms, t.timings.optimisation_ms,
                                       t.timings.total_ms, t.timings.map_wait_ms, t.timings.cpu_ms)
                        : std::string(",,,,,")) +
               "," + std::to_string(r.result.dynamicKeypoints) + "," +
               (timings ? mrpt::format("%.3f,%.3f,", r.result.dynamic_ms, r.result.queue_wait_ms)
                        : std::string(",,")) +
               semanticCsv(r.result, timings) + ",\n";
    }
    for (; nextSkipped != skipped_.end(); ++nextSkipped)
        csv += skippedCsvRow(*nextSkipped);
    return csv;
}

void RunLog::describeInput(core::JsonValue& metrics) const
{
    const size_t n = rows_.size();
    metrics.set("frames", static_cast<uint64_t>(n));
    metrics.set("frames_skipped", static_cast<uint64_t>(skipped_.size()));
    auto list = core::JsonValue::array();
    constexpr size_t kListed = 20;
    for (size_t i = 0; i < skipped_.size() && i < kListed; i++)
    {
        auto s = core::JsonValue::object();
        s.set("index", static_cast<uint64_t>(skipped_[i].index))
            .set("file", skipped_[i].file)
            .set("reason", skipped_[i].reason);
        list.push(s);
    }
    metrics.set("skipped", list);
    metrics.set("duration_s", lastStamp_ - firstStamp_);
    metrics.set("mean_valid_depth_fraction", n ? sumValidDepth_ / static_cast<double>(n) : 0.0);
    auto cam = core::JsonValue::object();
    cam.set("width", camera_.width).set("height", camera_.height).set("fx", camera_.fx);
    cam.set("fy", camera_.fy).set("cx", camera_.cx).set("cy", camera_.cy);
    metrics.set("camera", cam);
}

core::JsonValue RunLog::trackingJson() const
{
    auto j = core::JsonValue::object();
    j.set("frames_with_pose", static_cast<uint64_t>(withPose_))
        .set("frames_lost", static_cast<uint64_t>(lost_))
        .set("frames_discarded", static_cast<uint64_t>(discarded_))
        .set("relocalisations", static_cast<uint64_t>(relocalised_))
        .set("reanchors", static_cast<uint64_t>(reanchored_));
    uint64_t withMask = 0, raised = 0, stillMovable = 0, carried = 0;
    std::vector<double> ages;
    for (const auto& r : rows_)
    {
        raised += r.result.tracking.fallback == slam::TrackingFallback::RaisedWeights ? 1 : 0;
        stillMovable += r.result.tracking.fallback == slam::TrackingFallback::StillMovable ? 1 : 0;
        carried += r.result.tracking.fallback == slam::TrackingFallback::CarriedPose ? 1 : 0;
        if (r.result.maskAge)
        {
            withMask++;
            ages.push_back(static_cast<double>(*r.result.maskAge));
        }
    }
    j.set("frames_raised_weights", raised)
        .set("frames_still_movable", stillMovable)
        .set("frames_carried_pose", carried)
        .set("frames_with_mask", withMask)
        .set("median_mask_age", core::upperMedianInPlace(ages, 0.0));
    return j;
}

void RunLog::addTimings(core::JsonValue& timings) const
{
    std::vector<double> extraction, tracking, trackingCpu, mapWait, dynamic, wait, semantic,
        maskWait;
    for (const auto& r : rows_)
    {
        extraction.push_back(r.result.tracking.timings.extraction_ms);
        tracking.push_back(r.result.tracking.timings.total_ms);
        trackingCpu.push_back(r.result.tracking.timings.cpu_ms);
        mapWait.push_back(r.result.tracking.timings.map_wait_ms);
        dynamic.push_back(r.result.dynamic_ms);
        wait.push_back(r.result.queue_wait_ms);
        semantic.push_back(r.result.semantic_ms);
        maskWait.push_back(r.result.mask_wait_ms);
    }
    timings.set("feature_extraction", timingJson(extraction))
        .set("dynamic_filter", timingJson(dynamic))
        .set("semantic_evidence", timingJson(semantic))
        .set("mask_wait", timingJson(maskWait))
        .set("tracking", timingJson(tracking))
        .set("tracking_cpu", timingJson(trackingCpu))
        .set("map_wait", timingJson(mapWait))
        .set("keyframe_queue_wait", timingJson(wait));
}
}  // namespace smap::apps
