// The segmentation + mapping stage of semantic-mapper, in its own thread: keyframes arrive
// through a bounded queue in keyframe order; each is segmented (CNN + CRF), split into dynamic
// and static pixels by Algorithm 1, and its static pixels go into the maps. Tracking never waits
// for it unless the queue is full and [pipeline] when_full = wait.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "smap/core/LabelSet.h"
#include "smap/mapping/DynamicRegionFinder.h"
#include "smap/mapping/SemanticMapBuilder.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/pipeline/BoundedQueue.h"
#include "smap/pipeline/KeyFrameJob.h"
#include "smap/pipeline/MaskBoard.h"
#include "smap/segmentation/Segmenter.h"

namespace smap::pipeline
{
class KeyFrameWorker : public mrpt::system::COutputLogger
{
public:
    /// `segmenter` may be null (no segmentation: every pixel void, so Algorithm 1 only grows
    /// regions around the dynamic points). The thread starts at once.
    KeyFrameWorker(std::unique_ptr<segmentation::Segmenter> segmenter, core::LabelSet labels,
                   const mapping::DynamicRegionParameters& association,
                   const mapping::MapBuilderParameters& map, size_t queueCapacity);
    ~KeyFrameWorker() override;
    KeyFrameWorker(const KeyFrameWorker&) = delete;
    KeyFrameWorker& operator=(const KeyFrameWorker&) = delete;

    /// Called on the worker thread after each keyframe reached the maps, in keyframe order.
    using Observer = std::function<void(const KeyFrameJob&, const maps::CObservationSemanticRGBD&,
                                        const mapping::DynamicRegions&)>;
    void setObserver(Observer observer) { observer_ = std::move(observer); }

    /// Semantic evidence for tracking: after segmenting a keyframe, publish its pixels of the
    /// classes `movable` marks (by id) on `board` (sampled every `sampleStep` px); the board is
    /// closed when the worker stops or fails. With `newestFirst`, a worker that has fallen
    /// behind segments the newest queued keyframe before the oldest, so that tracking gets a
    /// fresh mask (a mask older than one already published is then not published); the maps
    /// still take the keyframes in order. Without it (tracking waits for a given keyframe's
    /// mask: reproducible runs) every mask is published, in order. Set before the first
    /// keyframe.
    void setMaskBoard(MaskBoard* board, std::vector<bool> movable, int sampleStep,
                      bool newestFirst);

    /// Queues a keyframe. wait = true blocks while the queue is full; false drops the keyframe
    /// then. Returns whether it was queued. Rethrows a failure of the worker thread.
    bool submit(KeyFrameJob job, bool wait);
    /// Processes what is queued, stops the thread, rethrows a failure of the worker thread.
    void finish();

    /// The maps, locked while `fn` runs (safe during a run).
    void withMaps(const std::function<void(mapping::SemanticMapBuilder&)>& fn);

    struct Stats
    {
        size_t keyframes = 0;  ///< processed
        size_t dropped = 0;    ///< queue full, when_full = drop
        size_t waits = 0;      ///< submissions that found the queue full, when_full = wait
        size_t queueHighWater = 0;
        std::vector<double> segmentation_ms, association_ms, insertion_ms, observer_ms;
        size_t dynamicPixels = 0, staticPixels = 0;
        size_t segmentedAhead = 0;  ///< keyframes segmented before older ones (newestFirst)
    };
    /// Copy of the statistics so far.
    Stats stats() const;
    const core::LabelSet& labels() const { return labels_; }
    std::string segmenterDescription() const;

private:
    void run();
    void process(KeyFrameJob& job);
    /// newestFirst: the newest queued keyframe segmented and its mask published now.
    void segmentNewestAhead();
    /// A keyframe's labels and their confidence at the frame's size.
    struct Labelled
    {
        cv::Mat labels, confidence;
        double ms = 0.0;  ///< the segmentation's time
    };
    Labelled segmentAtFrameSize(const core::RgbdFrame& f) const;
    /// The keyframe's mask onto the board unless a newer one is there already.
    void publishInOrder(const KeyFrameJob& job, const cv::Mat& labels);
    /// The keyframe's movable-class mask onto the board (when one is set).
    void publishMask(const KeyFrameJob& job, const cv::Mat& labels) const;

    std::unique_ptr<segmentation::Segmenter> segmenter_;
    core::LabelSet labels_;
    mapping::DynamicRegionFinder finder_;
    std::mutex mapMutex_;
    mapping::SemanticMapBuilder builder_;
    Observer observer_;
    MaskBoard* board_ = nullptr;
    std::vector<bool> movable_;
    int maskStep_ = 4;
    bool newestFirst_ = false;
    uint64_t newestPublished_ = 0;  ///< frame id of the newest mask published (+1; 0 = none)
    /// Keyframes segmented ahead of their turn, by frame id (worker thread only).
    std::map<uint64_t, Labelled> segmentedAhead_;
    BoundedQueue<KeyFrameJob> queue_;
    mutable std::mutex statsMutex_;
    Stats stats_;
    std::exception_ptr error_;
    std::thread thread_;
};
}  // namespace smap::pipeline
