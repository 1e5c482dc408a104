// The front end of semantic-mapper as a stream of prepared frames: one thread reads and decodes
// frames from the source, another extracts features and runs the dynamic filter
// (SemanticMapper::prepare), each feeding the next through a bounded queue, so that decoding,
// the front end and tracking overlap. With capacity 0 everything runs inline in next().
// Frames come out in source order; the result does not depend on the threads.
#pragma once

#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "smap/io/FrameSource.h"
#include "smap/pipeline/BoundedQueue.h"
#include "smap/pipeline/FrameSummary.h"
#include "smap/pipeline/SemanticMapper.h"

namespace smap::pipeline
{
class FrameFeeder
{
public:
    struct Item
    {
        size_t index = 0;  ///< 0-based position in the stream
        /// Set for a frame of the input that could not be read; `stats` and `frame` are empty.
        std::optional<io::SkippedFrame> skipped;
        FrameStats stats;
        SemanticMapper::PreparedFrame frame;
    };
    /// `stop` is polled before each read (Ctrl-C); `onPrepared` sees every prepared frame on
    /// the front-end thread (debug pictures).
    FrameFeeder(io::FrameSource& source, SemanticMapper& mapper, size_t capacity,
                std::function<bool()> stop, std::function<void(const Item&)> onPrepared = nullptr);
    ~FrameFeeder();
    FrameFeeder(const FrameFeeder&) = delete;
    FrameFeeder& operator=(const FrameFeeder&) = delete;

    /// The next prepared (or skipped) frame; nullopt at the end of the input or after `stop`.
    /// A failure of either thread (input that is no recording, an internal error) is rethrown
    /// here once the frames before it are consumed.
    std::optional<Item> next();
    /// Stops reading and joins the threads (also done by the destructor).
    void close();

    /// Milliseconds to read and decode each frame (complete once next() returned nullopt).
    std::vector<double> readMilliseconds() const;

private:
    struct Raw
    {
        size_t index = 0;
        std::optional<io::SkippedFrame> skipped;
        FrameStats stats;
        core::RgbdFrame frame;
    };
    std::optional<Raw> read();
    Item prepare(const Raw& raw);
    void fail();

    io::FrameSource& source_;
    SemanticMapper& mapper_;
    std::function<bool()> stop_;
    std::function<void(const Item&)> onPrepared_;
    const bool threaded_;
    BoundedQueue<Raw> raw_;
    BoundedQueue<Item> ready_;
    mutable std::mutex mutex_;
    std::exception_ptr error_;
    std::vector<double> readMs_;
    size_t nextIndex_ = 0;
    std::thread reader_;
    std::thread preparer_;
};
}  // namespace smap::pipeline
