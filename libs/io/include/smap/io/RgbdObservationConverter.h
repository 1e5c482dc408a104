// One MRPT RGB-D observation (mrpt::obs::CObservation3DRangeScan) as the frame the pipeline
// takes: colour image, depth in metres on the colour camera's grid, the colour camera. What a
// robot program calls on each observation of a live sensor (mrpt::hwdrivers::CGenericSensor),
// and what RawlogSource calls on each one it reads from a file.
//
// Handles images stored inside the observation or externally (relative paths resolved against
// the images folder given), range images in any rangeUnits, range_is_depth == false, and depth
// cameras that do not coincide with the colour camera (the depth is registered onto the colour
// image). The configuration's [camera] / [depth_camera] (FrameSourceParameters) override the
// observation's own intrinsics.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <memory>
#include <string>

#include "smap/core/RgbdFrame.h"
#include "smap/io/FrameSourceParameters.h"

namespace mrpt::obs
{
class CObservation3DRangeScan;
}

namespace smap::io
{
class RgbdObservationConverter : public mrpt::system::COutputLogger
{
public:
    /// `imagesDirectory`: the base of relative external image paths (for a rawlog, its
    /// "<stem>_Images" folder; empty: the current folder).
    explicit RgbdObservationConverter(const FrameSourceParameters& params,
                                      std::string imagesDirectory = "");
    ~RgbdObservationConverter() override;
    RgbdObservationConverter(RgbdObservationConverter&&) noexcept;
    RgbdObservationConverter& operator=(RgbdObservationConverter&&) noexcept;

    /// The frame (index 0, name the external colour image's stem or empty). Throws
    /// core::InputError naming `where` (e.g. "rawlog 'x' entry 12", "sensor 'KINECT'") and the
    /// value that is wrong: no range or intensity image, an unreadable external image, an
    /// unsupported image type, invalid intrinsics, a configured camera whose size differs
    /// from the images, a range image without any valid depth.
    core::RgbdFrame convert(const mrpt::obs::CObservation3DRangeScan& obs,
                            const std::string& where);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
}  // namespace smap::io
