// A bounded FIFO between two threads: push waits while the queue is full (or, with tryPush,
// gives up), pop waits until an item arrives or the queue is closed and drained.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace smap::pipeline
{
template <typename T>
class BoundedQueue
{
public:
    explicit BoundedQueue(size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

    /// Waits while full. Returns false (and drops the item) when the queue was closed. Sets
    /// *waited when it had to wait.
    bool push(T item, bool* waited = nullptr)
    {
        std::unique_lock<std::mutex> lock(mutex_);
        if (waited)
            *waited = items_.size() >= capacity_ && !closed_;
        notFull_.wait(lock, [&] { return items_.size() < capacity_ || closed_; });
        if (closed_)
            return false;
        items_.push_back(std::move(item));
        highWater_ = std::max(highWater_, items_.size());
        notEmpty_.notify_one();
        return true;
    }

    /// Never waits: false when full or closed.
    bool tryPush(T item)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (closed_ || items_.size() >= capacity_)
            return false;
        items_.push_back(std::move(item));
        highWater_ = std::max(highWater_, items_.size());
        notEmpty_.notify_one();
        return true;
    }

    /// Waits for an item; nullopt once the queue is closed and empty.
    std::optional<T> pop()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        notEmpty_.wait(lock, [&] { return !items_.empty() || closed_; });
        if (items_.empty())
            return std::nullopt;
        T item = std::move(items_.front());
        items_.pop_front();
        notFull_.notify_one();
        return item;
    }

    /// A copy of the newest item, when one is queued (the oldest stays first to pop).
    std::optional<T> newest() const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (items_.empty())
            return std::nullopt;
        return items_.back();
    }

    /// No more pushes; pop drains what is queued, then returns nullopt.
    void close()
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;
        notEmpty_.notify_all();
        notFull_.notify_all();
    }

    size_t size() const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return items_.size();
    }
    size_t capacity() const { return capacity_; }
    /// Most items ever queued at once.
    size_t highWater() const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return highWater_;
    }

private:
    const size_t capacity_;
    mutable std::mutex mutex_;
    std::condition_variable notEmpty_;
    std::condition_variable notFull_;
    std::deque<T> items_;
    size_t highWater_ = 0;
    bool closed_ = false;
};
}  // namespace smap::pipeline
