#include "smap/pipeline/MaskBoard.h"

#include "smap/core/Elapsed.h"

namespace smap::pipeline
{
void MaskBoard::expect(uint64_t frameId)
{
    std::lock_guard<std::mutex> lock(mutex_);
    // The worker may have published it already (it runs as soon as the keyframe is queued).
    const bool published = !masks_.empty() && masks_.back()->frameId() >= frameId;
    if (!closed_ && !published)
        pending_.push_back(frameId);
}

void MaskBoard::publish(MaskPtr mask)
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        while (!pending_.empty() && pending_.front() <= mask->frameId())
            pending_.pop_front();
        masks_.push_back(std::move(mask));
        while (masks_.size() > kKept)
            masks_.pop_front();
    }
    published_.notify_all();
}

void MaskBoard::close()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;
        pending_.clear();
    }
    published_.notify_all();
}

MaskBoard::Lookup MaskBoard::newest(uint64_t upTo, bool wait)
{
    Lookup out;
    std::unique_lock<std::mutex> lock(mutex_);
    if (wait && !pending_.empty() && pending_.front() <= upTo)
    {
        const auto t0 = std::chrono::steady_clock::now();
        published_.wait(lock, [&] { return pending_.empty() || pending_.front() > upTo; });
        out.wait_ms = core::millisecondsSince(t0);
    }
    for (auto it = masks_.rbegin(); it != masks_.rend(); ++it)
    {
        if ((*it)->frameId() <= upTo)
        {
            out.mask = *it;
            break;
        }
    }
    return out;
}
}  // namespace smap::pipeline
