#include "smap/io/FrameSourceParameters.h"

#include <mrpt/core/format.h>

#include <cmath>
#include <sstream>

#include "smap/core/InputError.h"

namespace smap::io
{
namespace
{
constexpr const char* kDepthSection = "depth_camera";

/// Three numbers "x y z" (commas allowed) from [depth_camera] `key`; `fallback` when absent.
Eigen::Vector3d readTriple(const mrpt::config::CConfigFileBase& cfg, const std::string& key,
                           const Eigen::Vector3d& fallback)
{
    const std::string text = cfg.read_string(kDepthSection, key, "");
    if (text.empty())
        return fallback;
    std::string spaced = text;
    for (char& ch : spaced)
        ch = ch == ',' ? ' ' : ch;
    std::istringstream in(spaced);
    Eigen::Vector3d v;
    std::string rest;
    if (!(in >> v.x() >> v.y() >> v.z()) || (in >> rest) || !v.allFinite())
        throw core::InputError(mrpt::format("[%s] %s = '%s' must be three numbers (x y z)",
                                            kDepthSection, key.c_str(), text.c_str()));
    return v;
}

void loadDepthCamera(const mrpt::config::CConfigFileBase& cfg, FrameSourceParameters& p)
{
    if (!cfg.sectionExists(kDepthSection))
        return;
    p.depth_camera = core::loadCamera(cfg, kDepthSection);
    const Eigen::Vector3d t = readTriple(cfg, "t_colour_depth", p.T_colour_depth.translation());
    const Eigen::AngleAxisd current(p.T_colour_depth.linear());
    const Eigen::Vector3d r =
        readTriple(cfg, "r_colour_depth", current.axis() * current.angle() * 180.0 / M_PI);
    constexpr double kLargestOffset = 1.0;  // m: farther apart is no RGB-D sensor
    if (t.norm() > kLargestOffset)
        throw core::InputError(mrpt::format(
            "[%s] t_colour_depth = %g %g %g: the cameras would be %.2f m apart (metres expected)",
            kDepthSection, t.x(), t.y(), t.z(), t.norm()));
    p.T_colour_depth = Eigen::Isometry3d::Identity();
    const double angle = r.norm() * M_PI / 180.0;
    if (angle > 0.0)
        p.T_colour_depth.linear() = Eigen::AngleAxisd(angle, r.normalized()).toRotationMatrix();
    p.T_colour_depth.translation() = t;
}
}  // namespace

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
    loadDepthCamera(cfg, *this);
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
    if (depth_camera)
    {
        core::saveCamera(*depth_camera, cfg, kDepthSection);
        const Eigen::Vector3d& t = T_colour_depth.translation();
        const Eigen::AngleAxisd r(T_colour_depth.linear());
        const Eigen::Vector3d rv = r.axis() * r.angle() * 180.0 / M_PI;
        cfg.write(kDepthSection, "t_colour_depth",
                  mrpt::format("%.17g %.17g %.17g", t.x(), t.y(), t.z()));
        cfg.write(kDepthSection, "r_colour_depth",
                  mrpt::format("%.17g %.17g %.17g", rv.x(), rv.y(), rv.z()));
    }
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
