// The keyframe hand-over that local mapping and loop closing share: keyframes handled in the
// order they come, on a worker thread of their own (tracking never waits) or, when not
// threaded, at once on the caller's thread (deterministic runs and tests).
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

namespace smap::slam
{
class KeyFrame;

class KeyFrameQueue
{
public:
    using Handler = std::function<void(const std::shared_ptr<KeyFrame>&)>;

    /// `handler` is called once per pushed keyframe: on the queue's own thread when `threaded`,
    /// else inside push().
    KeyFrameQueue(bool threaded, Handler handler);
    /// Stops the thread; a keyframe being handled is finished, queued ones are dropped.
    ~KeyFrameQueue();
    KeyFrameQueue(const KeyFrameQueue&) = delete;
    KeyFrameQueue& operator=(const KeyFrameQueue&) = delete;

    /// Queues `kf` (threaded) or handles it before returning. Ignored after stop().
    void push(const std::shared_ptr<KeyFrame>& kf);
    /// Keyframes waiting, not counting the one being handled.
    size_t waiting() const;
    /// True when nothing waits and nothing is being handled.
    bool idle() const;
    /// Blocks until idle (or stopped). Returns at once when not threaded.
    void waitUntilIdle();
    /// Stops taking keyframes and joins the thread after the keyframe being handled.
    void stop();

private:
    void run();

    Handler handler_;
    mutable std::mutex mutex_;
    std::condition_variable queued_;
    std::condition_variable idle_;
    std::deque<std::shared_ptr<KeyFrame>> queue_;
    bool busy_ = false;
    bool stopped_ = false;
    std::unique_ptr<std::thread> thread_;
};
}  // namespace smap::slam
