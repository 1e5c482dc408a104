// Options of every frame source, loaded once from the configuration.
//
// [input]   max_frames (0 = all), stride (every Nth frame), max_skipped_fraction (more frames
//           unreadable than this fraction make a run bad input)
// [tum]     depth_factor (raw units per metre: TUM 5000, 7-Scenes 1000), max_dt (s),
//           use_associations (use associations.txt when present)
// [rawlog]  sensor_label (empty: the first RGB-D sensor seen)
// [camera]  optional intrinsics of the colour image (width height fx fy cx cy k1 k2 p1 p2 k3):
//           for TUM folders the apps fall back on the folder's camera.ini or name preset
//           (pipeline/InputPreset.h), TumSource itself on the ROS default; overrides the
//           observation's intrinsics for rawlogs.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <optional>
#include <string>

#include "smap/core/PinholeCamera.h"

namespace smap::io
{
struct FrameSourceParameters : public mrpt::config::CLoadableOptions
{
    size_t max_frames = 0;
    size_t stride = 1;
    /// Unreadable frames are skipped; more than this fraction of them (0 - 1) makes the run
    /// bad input (semantic-mapper writes its outputs, then exits with 2).
    double max_skipped_fraction = 0.5;

    double tum_depth_factor = 5000.0;
    double tum_max_dt = 0.02;
    bool tum_use_associations = true;

    std::string rawlog_sensor_label;

    std::optional<core::PinholeCamera> camera;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};

/// The ROS/TUM "default" Kinect intrinsics (640x480, f = 525, c = (319.5, 239.5)), used for a TUM
/// folder when no [camera] is configured.
core::PinholeCamera defaultKinectCamera();
}  // namespace smap::io
