#include "smap/io/FrameSourceParameters.h"

#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::io
{
void FrameSourceParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string&)
{
    const int maxFrames = cfg.read_int("input", "max_frames", static_cast<int>(max_frames));
    const int strideValue = cfg.read_int("input", "stride", static_cast<int>(stride));
    if (maxFrames < 0)
        throw core::InputError(mrpt::format("[input] max_frames = %d must be >= 0", maxFrames));
    if (strideValue < 1)
        throw core::InputError(mrpt::format("[input] stride = %d must be >= 1", strideValue));
    max_frames = static_cast<size_t>(maxFrames);
    stride = static_cast<size_t>(strideValue);
    max_skipped_fraction = cfg.read_double("input", "max_skipped_fraction", max_skipped_fraction);
    if (!(max_skipped_fraction >= 0.0 && max_skipped_fraction <= 1.0))
        throw core::InputError(mrpt::format("[input] max_skipped_fraction = %g must be in [0, 1]",
                                            max_skipped_fraction));

    tum_depth_factor = cfg.read_double("tum", "depth_factor", tum_depth_factor);
    tum_max_dt = cfg.read_double("tum", "max_dt", tum_max_dt);
    tum_use_associations = cfg.read_bool("tum", "use_associations", tum_use_associations);
    if (!(tum_depth_factor > 0.0))
        throw core::InputError(
            mrpt::format("[tum] depth_factor = %g must be > 0", tum_depth_factor));
    if (!(tum_max_dt > 0.0))
        throw core::InputError(mrpt::format("[tum] max_dt = %g must be > 0", tum_max_dt));

    rawlog_sensor_label = cfg.read_string("rawlog", "sensor_label", rawlog_sensor_label);

    // A [camera] section, even a partial one, must be complete and valid.
    if (cfg.sectionExists("camera"))
        camera = core::loadCamera(cfg, "camera");
}

void FrameSourceParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                             const std::string&) const
{
    cfg.write("input", "max_frames", static_cast<int>(max_frames));
    cfg.write("input", "stride", static_cast<int>(stride));
    cfg.write("input", "max_skipped_fraction", max_skipped_fraction);
    cfg.write("tum", "depth_factor", tum_depth_factor);
    cfg.write("tum", "max_dt", tum_max_dt);
    cfg.write("tum", "use_associations", tum_use_associations);
    cfg.write("rawlog", "sensor_label", rawlog_sensor_label);
    if (camera)
        core::saveCamera(*camera, cfg, "camera");
}

core::PinholeCamera defaultKinectCamera()
{
    core::PinholeCamera c;
    c.width = 640;
    c.height = 480;
    c.fx = 525.0;
    c.fy = 525.0;
    c.cx = 319.5;
    c.cy = 239.5;
    return c;
}
}  // namespace smap::io
