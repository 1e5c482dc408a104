// Frames from an MRPT rawlog, streamed entry by entry (never the whole file in memory).
//
// Handles both rawlog layouts (CSensoryFrame + CActionCollection pairs, and bare observations),
// plain or gzip files, images stored inside the rawlog or externally in "<name>_Images/" next
// to it (searched as RawLogViewer does), range images in any rangeUnits, range_is_depth ==
// false, and depth cameras that do not coincide with the colour camera (the depth is
// registered onto the colour image).
#pragma once

#include <map>
#include <memory>

#include "smap/io/FrameSource.h"

namespace smap::io
{
class RawlogSource : public FrameSource
{
public:
    /// Opens the file; throws core::InputError when it cannot be opened.
    RawlogSource(const std::string& path, const FrameSourceParameters& params);
    ~RawlogSource() override;

    /// An observation whose images cannot be used (a missing or damaged external image, no
    /// valid depth, bad intrinsics) is a skipped frame. Damage in the file itself (a recording
    /// cut short mid-entry, corrupt bytes) ends the input there with a warning naming the
    /// rawlog and the entry (endedEarly() says the same). Throws core::InputError when not even
    /// the first entry can be read (not a rawlog), or when the rawlog ends without having held
    /// any usable RGB-D observation (the message lists the classes it did contain).
    std::optional<FrameRead> read() override;
    std::string endedEarly() const override;
    std::string description() const override;
    std::string groundTruthPath() const override;

    /// Base of relative external image paths: the first existing of "<dir>/<stem>_Images",
    /// "_images", "_IMAGES", else "<dir>/Images" (MRPT's own search order).
    const std::string& imagesDirectory() const;
    /// Entries read so far, by MRPT class name (observations inside sensory frames included).
    const std::map<std::string, size_t>& classCounts() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
}  // namespace smap::io
