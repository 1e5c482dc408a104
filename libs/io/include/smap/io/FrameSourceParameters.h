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
// [depth_camera] optional, for depth not registered to colour (7-Scenes, a raw Kinect): the
//           intrinsics of the depth images (same keys as [camera]) and the depth-to-colour
//           extrinsic T_colour_depth as t_colour_depth = x y z (metres) and r_colour_depth = a
//           rotation vector in degrees (axis times angle). Each depth image is then put on the
//           colour grid when read (io/DepthToColour.h); for rawlogs it replaces the
//           observation's depth camera and relativePoseIntensityWRTDepth.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Geometry>
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

    /// The depth camera when depth is not registered to colour; with it T_colour_depth maps
    /// points from its optical frame to the colour camera's (x right, y down, z forward).
    std::optional<core::PinholeCamera> depth_camera;
    Eigen::Isometry3d T_colour_depth = Eigen::Isometry3d::Identity();

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};

/// The ROS/TUM "default" Kinect intrinsics (640x480, f = 525, c = (319.5, 239.5)), used for a TUM
/// folder when no [camera] is configured.
core::PinholeCamera defaultKinectCamera();
}  // namespace smap::io
