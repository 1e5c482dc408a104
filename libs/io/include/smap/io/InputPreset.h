// The configuration a recording folder implies when the user gives no camera: the folder's own
// camera.ini (smap-synth writes one), else the preset its name names. TUM RGB-D folders are named
// "rgbd_dataset_freiburg<N>_<sequence>", Bonn RGB-D Dynamic's "rgbd_bonn_<sequence>" and ours of
// 7-Scenes "7scenes-<scene>"; read without their preset they get the wrong intrinsics (and
// 7-Scenes a depth scale five times off).
// loadAppConfiguration applies it first, under the user's files and overrides, when the user's
// configuration has no [camera] of its own.
#pragma once

#include <optional>
#include <string>

namespace smap::io
{
/// A recording folder's own preset: the [camera] (and [tum] depth_factor) to read it with.
constexpr const char* kFolderCameraFile = "camera.ini";

struct InputPreset
{
    std::string source;  ///< where the text came from: "config/tum_fr3.ini", "DIR/camera.ini"
    std::string reason;  ///< why it applies: "its name says TUM RGB-D freiburg3"
    std::string text;    ///< INI text
};

/// The preset for `input` when it is an existing folder that holds kFolderCameraFile (read
/// now; InputError when unreadable), or whose own name (not a parent's) contains, ignoring case,
/// one of "freiburg1", "freiburg2", "freiburg3" (config/tum_fr<N>.ini, built in) or "7scenes",
/// "7-scenes", "7_scenes" (config/7scenes.ini) or "rgbd_bonn" (config/bonn.ini); nothing otherwise,
/// when the name says two datasets, or for an smap-synth output without kFolderCameraFile (written
/// before smap-synth wrote one: its depth is at 5000 units per metre whatever its source, so a
/// composite named after 7-Scenes must not get 7-Scenes' depth factor).
std::optional<InputPreset> presetForInput(const std::string& input);

/// True when `folder` holds an smap-synth output: its meta.json names the generator.
bool isSmapSynthOutput(const std::string& folder);
}  // namespace smap::io
