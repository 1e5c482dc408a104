#include "KeyFrameQueue.h"

namespace smap::slam
{
KeyFrameQueue::KeyFrameQueue(bool threaded, Handler handler) : handler_(std::move(handler))
{
    if (threaded)
        thread_ = std::make_unique<std::thread>([this] { run(); });
}

KeyFrameQueue::~KeyFrameQueue()
{
    stop();
}

void KeyFrameQueue::push(const std::shared_ptr<KeyFrame>& kf)
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopped_)
            return;
        if (thread_)
            queue_.push_back(kf);
    }
    if (thread_)
        queued_.notify_one();
    else
        handler_(kf);
}

size_t KeyFrameQueue::waiting() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return queue_.size();
}

bool KeyFrameQueue::idle() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return queue_.empty() && !busy_;
}

void KeyFrameQueue::waitUntilIdle()
{
    if (!thread_)
        return;
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [this] { return stopped_ || (queue_.empty() && !busy_); });
}

void KeyFrameQueue::stop()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopped_ = true;
    }
    queued_.notify_all();
    if (thread_ && thread_->joinable())
        thread_->join();
    idle_.notify_all();
}

void KeyFrameQueue::run()
{
    for (;;)
    {
        std::shared_ptr<KeyFrame> kf;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            queued_.wait(lock, [this] { return stopped_ || !queue_.empty(); });
            if (stopped_)
                return;
            kf = queue_.front();
            queue_.pop_front();
            busy_ = true;
        }
        handler_(kf);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            busy_ = false;
        }
        idle_.notify_all();
    }
}
}  // namespace smap::slam
