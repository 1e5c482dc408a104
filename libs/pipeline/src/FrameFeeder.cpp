#include "smap/pipeline/FrameFeeder.h"

#include "smap/core/Elapsed.h"

namespace smap::pipeline
{
FrameFeeder::FrameFeeder(io::FrameSource& source, SemanticMapper& mapper, size_t capacity,
                         std::function<bool()> stop, std::function<void(const Item&)> onPrepared)
    : source_(source),
      mapper_(mapper),
      stop_(std::move(stop)),
      onPrepared_(std::move(onPrepared)),
      threaded_(capacity > 0),
      raw_(capacity),
      ready_(capacity)
{
    if (!threaded_)
        return;
    reader_ = std::thread(
        [this]
        {
            try
            {
                while (auto r = read())
                    if (!raw_.push(std::move(*r)))
                        break;
            }
            catch (...)
            {
                fail();
            }
            raw_.close();
        });
    preparer_ = std::thread(
        [this]
        {
            try
            {
                while (auto r = raw_.pop())
                    if (!ready_.push(prepare(*r)))
                        break;
            }
            catch (...)
            {
                fail();
                raw_.close();
            }
            ready_.close();
        });
}

FrameFeeder::~FrameFeeder()
{
    close();
}

void FrameFeeder::close()
{
    raw_.close();
    ready_.close();
    if (reader_.joinable())
        reader_.join();
    if (preparer_.joinable())
        preparer_.join();
}

void FrameFeeder::fail()
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_)
        error_ = std::current_exception();
}

std::optional<FrameFeeder::Raw> FrameFeeder::read()
{
    if (stop_ && stop_())
        return std::nullopt;
    const auto t0 = std::chrono::steady_clock::now();
    auto got = source_.read();
    if (!got)
        return std::nullopt;
    Raw r;
    r.index = nextIndex_++;
    if (auto* skipped = std::get_if<io::SkippedFrame>(&*got))
    {
        r.skipped = std::move(*skipped);
        return r;
    }
    auto& frame = std::get<core::RgbdFrame>(*got);
    frame.validate();
    r.stats = computeFrameStats(frame);
    r.frame = std::move(frame);
    const double ms = core::millisecondsSince(t0);
    std::lock_guard<std::mutex> lock(mutex_);
    readMs_.push_back(ms);
    return r;
}

FrameFeeder::Item FrameFeeder::prepare(const Raw& raw)
{
    Item item;
    item.index = raw.index;
    item.skipped = raw.skipped;
    if (item.skipped)
        return item;
    item.stats = raw.stats;
    item.frame = mapper_.prepare(raw.frame);
    if (onPrepared_)
        onPrepared_(item);
    return item;
}

std::optional<FrameFeeder::Item> FrameFeeder::next()
{
    std::optional<Item> item;
    if (threaded_)
        item = ready_.pop();
    else if (auto r = read())
        item = prepare(*r);
    if (!item)
    {
        close();
        std::lock_guard<std::mutex> lock(mutex_);
        if (error_)
            std::rethrow_exception(error_);
    }
    return item;
}

std::vector<double> FrameFeeder::readMilliseconds() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return readMs_;
}
}  // namespace smap::pipeline
