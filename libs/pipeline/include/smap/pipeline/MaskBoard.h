// Where the keyframe worker leaves the movable-class masks of the keyframes it segmented, for the
// tracker to use on later frames (semantic evidence). Tracking announces each keyframe it queues
// (expect); the worker publishes its mask once segmented, in keyframe order; a frame asks for the
// newest mask of the keyframes up to some frame, and may wait for a late one so that a run gives
// the same result whatever the threads' timing.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>

#include "smap/dynamic/MovableMask.h"

namespace smap::pipeline
{
class MaskBoard
{
public:
    using MaskPtr = std::shared_ptr<const dynamic::MovableMask>;

    /// A keyframe of tracker frame `frameId` was queued for segmentation (increasing ids;
    /// nothing to wait for when its mask is published already).
    void expect(uint64_t frameId);
    /// The mask of the keyframe of `frameId` (in the order expected; an empty mask when the
    /// keyframe shows no movable class).
    void publish(MaskPtr mask);
    /// No more masks will come (the worker stopped or failed): nothing waits any longer.
    void close();

    struct Lookup
    {
        MaskPtr mask;          ///< null: no keyframe up to the bound has been segmented
        double wait_ms = 0.0;  ///< time spent waiting for the worker
    };
    /// The newest published mask of a keyframe with frameId <= upTo. With `wait`, first waits
    /// until every expected keyframe up to `upTo` is published (or the board is closed).
    Lookup newest(uint64_t upTo, bool wait);

private:
    /// Masks kept: enough for any bound a frame can ask for (keyframes are frames apart).
    static constexpr size_t kKept = 8;

    std::mutex mutex_;
    std::condition_variable published_;
    std::deque<uint64_t> pending_;  ///< expected, not yet published, in order
    std::deque<MaskPtr> masks_;     ///< published, oldest first
    bool closed_ = false;
};
}  // namespace smap::pipeline
