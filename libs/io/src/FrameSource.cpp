#include "smap/io/FrameSource.h"

#include <mrpt/core/format.h>

#include <filesystem>

#include "smap/core/InputError.h"
#include "smap/io/RawlogSource.h"
#include "smap/io/TumSource.h"

namespace fs = std::filesystem;

namespace smap::io
{
namespace
{
/// Applies max_frames and stride on top of any source, keeping frame indices of the source.
class SubsampledSource : public FrameSource
{
public:
    SubsampledSource(std::unique_ptr<FrameSource> inner, size_t maxFrames, size_t stride)
        : FrameSource("SubsampledSource"),
          inner_(std::move(inner)),
          maxFrames_(maxFrames),
          stride_(stride)
    {
    }

    std::optional<FrameRead> read() override
    {
        if (maxFrames_ != 0 && delivered_ >= maxFrames_)
            return std::nullopt;
        for (;;)
        {
            auto f = inner_->read();
            if (!f)
                return std::nullopt;
            if (seen_++ % stride_ != 0)
                continue;
            delivered_++;
            return f;
        }
    }
    std::string description() const override { return inner_->description(); }
    std::optional<size_t> sizeHint() const override
    {
        auto n = inner_->sizeHint();
        if (!n)
            return std::nullopt;
        size_t k = (*n + stride_ - 1) / stride_;
        if (maxFrames_ != 0)
            k = std::min(k, maxFrames_);
        return k;
    }
    std::string groundTruthPath() const override { return inner_->groundTruthPath(); }
    std::string endedEarly() const override { return inner_->endedEarly(); }

private:
    std::unique_ptr<FrameSource> inner_;
    size_t maxFrames_;
    size_t stride_;
    size_t seen_ = 0;
    size_t delivered_ = 0;
};
}  // namespace

std::optional<core::RgbdFrame> FrameSource::next()
{
    while (auto r = read())
    {
        if (auto* frame = std::get_if<core::RgbdFrame>(&*r))
            return std::move(*frame);
    }
    return std::nullopt;
}

FrameRead FrameSource::skip(SkippedFrame frame)
{
    skipped_++;
    constexpr size_t kEachUpTo = 20, kThenEvery = 100;
    if (skipped_ <= kEachUpTo)
        MRPT_LOG_WARN_FMT("frame %zu skipped: '%s': %s", frame.index, frame.file.c_str(),
                          frame.reason.c_str());
    else if (skipped_ % kThenEvery == 0)
        MRPT_LOG_WARN_FMT("frame %zu skipped: '%s': %s (%zu frames skipped so far)", frame.index,
                          frame.file.c_str(), frame.reason.c_str(), skipped_);
    return frame;
}

std::unique_ptr<FrameSource> openFrameSource(const std::string& path,
                                             const FrameSourceParameters& params)
{
    std::unique_ptr<FrameSource> src;
    if (fs::is_directory(path))
        src = std::make_unique<TumSource>(path, params);
    else if (fs::is_regular_file(path))
        src = std::make_unique<RawlogSource>(path, params);
    else
        throw core::InputError(mrpt::format(
            "input '%s' does not exist (expected a TUM RGB-D folder or an MRPT .rawlog file)",
            path.c_str()));
    if (params.max_frames == 0 && params.stride == 1)
        return src;
    return std::make_unique<SubsampledSource>(std::move(src), params.max_frames, params.stride);
}
}  // namespace smap::io
