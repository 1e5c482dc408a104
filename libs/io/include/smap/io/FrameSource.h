// Where RGB-D frames come from: a TUM RGB-D folder or an MRPT rawlog, read one frame at a time.
// A frame whose images cannot be read is reported as skipped, never fatal: one bad frame in an
// hour-long recording must not cost the run.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "smap/core/RgbdFrame.h"
#include "smap/io/FrameSourceParameters.h"

namespace smap::io
{
/// A frame of the recording that could not be read: which one, the file at fault and why.
struct SkippedFrame
{
    size_t index = 0;        ///< position in the source, as core::RgbdFrame::index
    double timestamp = 0.0;  ///< from the list or entry when known, else 0
    std::string name;        ///< what core::RgbdFrame::name would have been, when known
    std::string file;        ///< the image (or entry) at fault
    std::string reason;      ///< e.g. "missing", "empty (0 bytes)", "cannot be decoded"
};

/// One step through a recording: a frame, or a frame that had to be skipped.
using FrameRead = std::variant<core::RgbdFrame, SkippedFrame>;

class FrameSource : public mrpt::system::COutputLogger
{
public:
    explicit FrameSource(const std::string& loggerName) : COutputLogger(loggerName) {}
    ~FrameSource() override = default;

    /// The next frame or skipped frame, or std::nullopt at the end. A skipped frame has been
    /// warned about (by the source that found it). Input that is no recording at all (not a
    /// rawlog, no lists) throws core::InputError naming the file.
    virtual std::optional<FrameRead> read() = 0;
    /// The next readable frame, passing over skipped ones; std::nullopt at the end.
    std::optional<core::RgbdFrame> next();

    /// Human-readable description (kind and path).
    virtual std::string description() const = 0;
    /// Number of frames when known in advance (TUM folders), else nullopt (rawlogs stream).
    virtual std::optional<size_t> sizeHint() const { return std::nullopt; }
    /// Path of a ground-truth trajectory (TUM format) shipped with the input, or empty.
    virtual std::string groundTruthPath() const { return {}; }
    /// Why the input ended before its end (a rawlog damaged or cut short mid-entry), once
    /// read() has returned std::nullopt; empty when it was read to its end.
    virtual std::string endedEarly() const { return {}; }

protected:
    /// Warns about `frame` (every one of the first 20 of a source, then every 100th with the
    /// count so far) and returns it as a FrameRead.
    FrameRead skip(SkippedFrame frame);

private:
    size_t skipped_ = 0;
};

/// Opens a TUM RGB-D folder (a directory with rgb.txt, or associations.txt) or an MRPT rawlog
/// file (plain or gzip). Applies [input] max_frames and stride (skipped frames count as frames
/// of the input). Throws core::InputError when the path is neither.
std::unique_ptr<FrameSource> openFrameSource(const std::string& path,
                                             const FrameSourceParameters& params);
}  // namespace smap::io
