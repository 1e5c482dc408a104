// KeyFrameWorker: keyframes reach the maps in order; a full queue waits or drops as configured;
// a failing segmenter surfaces on the tracking side; a worker that has fallen behind gives
// tracking the newest keyframe's mask first.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <thread>

#include "smap/core/InputError.h"
#include "smap/pipeline/KeyFrameWorker.h"
#include "smap/pipeline/MaskBoard.h"

using namespace smap;

namespace
{
/// Holds the segmentation of the frame named "gated" until the test opens it, so that the
/// test knows the worker is busy while it queues more keyframes (however loaded the machine).
struct Gate
{
    std::promise<void> entered, open;
};

/// Labels everything `label` after `delay`; throws on the frame named "bad".
class SlowSegmenter : public segmentation::Segmenter
{
public:
    SlowSegmenter(std::chrono::milliseconds delay, int label, Gate* gate)
        : Segmenter("slow", core::LabelSet::pascalVoc()), delay_(delay), label_(label), gate_(gate)
    {
    }
    segmentation::SegmentationResult segmentNative(const core::RgbdFrame& frame) override
    {
        if (frame.name == "bad")
            throw core::InputError("no label image for frame 'bad'");
        if (gate_ && frame.name == "gated")
        {
            gate_->entered.set_value();
            gate_->open.get_future().wait();
        }
        std::this_thread::sleep_for(delay_);
        const int n = static_cast<int>(labels().size());
        cv::Mat p(n, frame.colour.cols * frame.colour.rows, CV_32FC1, cv::Scalar(0.0f));
        p.row(label_).setTo(1.0f);
        return segmentation::SegmentationResult::fromProbabilities(p, frame.colour.cols,
                                                                   frame.colour.rows);
    }
    std::string description() const override { return "slow test segmenter"; }

private:
    std::chrono::milliseconds delay_;
    int label_;
    Gate* gate_;
};

pipeline::KeyFrameJob job(uint64_t k, double z, const std::string& name = "f")
{
    pipeline::KeyFrameJob j;
    j.keyframe = k;
    j.frameId = k;
    j.frame.camera.width = 32;
    j.frame.camera.height = 24;
    j.frame.camera.fx = j.frame.camera.fy = 30.0;
    j.frame.camera.cx = 15.5;
    j.frame.camera.cy = 11.5;
    j.frame.colour = cv::Mat(24, 32, CV_8UC3, cv::Scalar(50, 100, 150));
    j.frame.depth = cv::Mat(24, 32, CV_32FC1, cv::Scalar(2.0f));
    j.frame.timestamp = static_cast<double>(k);
    j.frame.name = name;
    j.T_world_cam = mrpt::poses::CPose3D(0.0, 0.0, z, 0.0, 0.0, 0.0);
    return j;
}

std::unique_ptr<pipeline::KeyFrameWorker> worker(std::chrono::milliseconds delay, size_t queue,
                                                 Gate* gate = nullptr)
{
    mapping::MapBuilderParameters map;
    map.octomap = false;
    return std::make_unique<pipeline::KeyFrameWorker>(
        std::make_unique<SlowSegmenter>(delay, 9, gate), core::LabelSet::pascalVoc(),
        mapping::DynamicRegionParameters(), map, queue);
}
}  // namespace

TEST(KeyFrameWorker, WaitingQueueMapsEveryKeyframeInOrder)
{
    auto w = worker(std::chrono::milliseconds(30), 1);
    std::vector<uint64_t> seen;
    w->setObserver(
        [&](const pipeline::KeyFrameJob& j, const maps::CObservationSemanticRGBD& obs,
            const mapping::DynamicRegions&)
        {
            seen.push_back(j.keyframe);
            EXPECT_EQ(obs.labels.at<uint8_t>(0, 0), 9);
            EXPECT_EQ(obs.sensorPose.z(), static_cast<double>(j.keyframe));
        });
    for (uint64_t k = 0; k < 5; ++k)
        EXPECT_TRUE(w->submit(job(k, static_cast<double>(k)), true));
    w->finish();
    EXPECT_EQ(seen, (std::vector<uint64_t>{0, 1, 2, 3, 4}));
    const auto s = w->stats();
    EXPECT_EQ(s.keyframes, 5u);
    EXPECT_EQ(s.dropped, 0u);
    EXPECT_GE(s.waits, 1u) << "a 1-keyframe queue behind a 30 ms segmenter fills up";
    EXPECT_EQ(s.segmentation_ms.size(), 5u);
    w->withMaps(
        [](mapping::SemanticMapBuilder& b)
        {
            ASSERT_EQ(b.contributions().size(), 5u);
            for (size_t i = 0; i < 5; ++i)
                EXPECT_EQ(b.contributions()[i].keyframe, i);
            // Five walls, 1 m apart along z, all labelled chair.
            for (const auto& p : b.pointsMap().points())
                EXPECT_EQ(p.label, 9);
        });
}

TEST(KeyFrameWorker, DroppingQueueNeverBlocksTracking)
{
    // Five more keyframes arrive while the first is segmented (held at the gate): one runs,
    // one waits in the queue, the rest are dropped rather than stalling tracking.
    Gate gate;
    auto w = worker(std::chrono::milliseconds(0), 1, &gate);
    size_t queued = w->submit(job(0, 0.0, "gated"), false) ? 1 : 0;
    gate.entered.get_future().wait();
    for (uint64_t k = 1; k < 6; ++k)
        queued += w->submit(job(k, 0.0), false) ? 1 : 0;
    gate.open.set_value();
    w->finish();
    const auto s = w->stats();
    EXPECT_EQ(s.keyframes, queued);
    EXPECT_EQ(s.dropped, 6u - queued);
    EXPECT_GE(s.dropped, 3u);
    EXPECT_EQ(s.waits, 0u);
}

TEST(KeyFrameWorker, SegmenterFailureReachesTheCaller)
{
    auto w = worker(std::chrono::milliseconds(0), 4);
    EXPECT_TRUE(w->submit(job(0, 0.0, "bad"), true));
    // The failure is reported at the latest by finish(), with its message.
    try
    {
        for (uint64_t k = 1; k < 50; ++k)
        {
            w->submit(job(k, 0.0), true);
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        w->finish();
        FAIL() << "the segmenter's error was swallowed";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("'bad'"), std::string::npos) << e.what();
    }
}

namespace
{
/// Keyframes 1-5 queued while keyframe 0 is being segmented (held at the gate until all are
/// queued); returns the frame id of the newest mask on the board up to each keyframe (-1:
/// none) and checks that the maps took them in order.
std::vector<int> masksAfterABacklog(bool newestFirst, size_t& segmentedAhead)
{
    Gate gate;
    auto w = worker(std::chrono::milliseconds(0), 8, &gate);
    pipeline::MaskBoard board;
    std::vector<bool> movable(core::LabelSet::pascalVoc().size(), false);
    movable[9] = true;
    w->setMaskBoard(&board, movable, 4, newestFirst);
    std::vector<uint64_t> mapped;
    w->setObserver(
        [&](const pipeline::KeyFrameJob& j, const maps::CObservationSemanticRGBD& obs,
            const mapping::DynamicRegions&)
        {
            mapped.push_back(j.keyframe);
            EXPECT_EQ(obs.labels.at<uint8_t>(0, 0), 9);
        });
    EXPECT_TRUE(w->submit(job(0, 0.0, "gated"), true));
    gate.entered.get_future().wait();
    for (uint64_t k = 1; k < 6; ++k)
        EXPECT_TRUE(w->submit(job(k, static_cast<double>(k)), true));
    gate.open.set_value();
    w->finish();
    EXPECT_EQ(mapped, (std::vector<uint64_t>{0, 1, 2, 3, 4, 5}));
    const auto s = w->stats();
    EXPECT_EQ(s.keyframes, 6U);
    EXPECT_EQ(s.segmentation_ms.size(), 6U) << "each keyframe segmented once";
    segmentedAhead = s.segmentedAhead;
    std::vector<int> newest;
    for (uint64_t k = 0; k < 6; ++k)
    {
        const auto l = board.newest(k, false);
        newest.push_back(l.mask ? static_cast<int>(l.mask->frameId()) : -1);
    }
    return newest;
}
}  // namespace

TEST(KeyFrameWorker, BehindItSegmentsTheNewestKeyFrameFirst)
{
    size_t ahead = 0;
    const std::vector<int> newest = masksAfterABacklog(true, ahead);
    EXPECT_GE(ahead, 1U);
    // Keyframe 5's mask came before those of 1-4, which were then too old to publish.
    EXPECT_EQ(newest[5], 5);
    for (size_t k = 1; k < 5; ++k)
        EXPECT_LE(newest[k], 0) << "keyframe " << k;
}

TEST(KeyFrameWorker, InOrderEveryMaskIsPublished)
{
    size_t ahead = 0;
    const std::vector<int> newest = masksAfterABacklog(false, ahead);
    EXPECT_EQ(ahead, 0U);
    EXPECT_EQ(newest, (std::vector<int>{0, 1, 2, 3, 4, 5}));
}
