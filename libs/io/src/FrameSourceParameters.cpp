#include "smap/io/FrameSourceParameters.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>

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

std::optional<core::PinholeCamera> tumCameraFromFolderName(const std::string& folder)
{
    // The folder's own name ("data/rgbd_dataset_freiburg1_xyz/" -> "rgbd_dataset_freiburg1_xyz").
    std::filesystem::path path(folder);
    if (!path.has_filename())
        path = path.parent_path();
    std::string name = path.filename().string();
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });

    struct Published
    {
        const char* tag;
        double fx, fy, cx, cy;
        std::array<double, 5> distortion;  // k1 k2 p1 p2 k3
    };
    // TUM RGB-D's published colour calibrations (freiburg3's images come undistorted).
    static constexpr std::array<Published, 3> kPublished{{
        {"freiburg1", 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}},
        {"freiburg2", 520.9, 521.0, 325.1, 249.7, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172}},
        {"freiburg3", 535.4, 539.2, 320.1, 247.6, {0.0, 0.0, 0.0, 0.0, 0.0}},
    }};
    const Published* match = nullptr;
    for (const auto& p : kPublished)
    {
        if (name.find(p.tag) == std::string::npos)
            continue;
        if (match != nullptr)
            return std::nullopt;  // names two cameras: no guess
        match = &p;
    }
    if (match == nullptr)
        return std::nullopt;
    core::PinholeCamera c;
    c.width = 640;
    c.height = 480;
    c.fx = match->fx;
    c.fy = match->fy;
    c.cx = match->cx;
    c.cy = match->cy;
    c.distortion = match->distortion;
    return c;
}
}  // namespace smap::io
