// Where RGB-D frames come from: a TUM RGB-D folder or an MRPT rawlog, read one frame at a time.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <memory>
#include <optional>
#include <string>

#include "smap/core/RgbdFrame.h"
#include "smap/io/FrameSourceParameters.h"

namespace smap::io
{
class FrameSource : public mrpt::system::COutputLogger
{
public:
    explicit FrameSource(const std::string& loggerName) : COutputLogger(loggerName) {}
    ~FrameSource() override = default;

    /// The next frame, or std::nullopt at the end. Bad data (missing image file, corrupt entry)
    /// throws core::InputError naming the file.
    virtual std::optional<core::RgbdFrame> next() = 0;
    /// Human-readable description (kind and path).
    virtual std::string description() const = 0;
    /// Number of frames when known in advance (TUM folders), else nullopt (rawlogs stream).
    virtual std::optional<size_t> sizeHint() const { return std::nullopt; }
    /// Path of a ground-truth trajectory (TUM format) shipped with the input, or empty.
    virtual std::string groundTruthPath() const { return {}; }
};

/// Opens a TUM RGB-D folder (a directory with rgb.txt, or associations.txt) or an MRPT rawlog
/// file (plain or gzip). Applies [input] max_frames and stride. Throws core::InputError when the
/// path is neither.
std::unique_ptr<FrameSource> openFrameSource(const std::string& path,
                                             const FrameSourceParameters& params);
}  // namespace smap::io
