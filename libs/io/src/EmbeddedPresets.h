// The text of the camera presets in config/, compiled in (EmbeddedPresets.cpp is generated from
// the .ini files by CMake).
#pragma once

#include <string_view>

namespace smap::io::detail
{
/// INI text of config/<file> as it was at build time, for the files listed in SMAP_PRESET_FILES
/// (libs/pipeline/CMakeLists.txt: tum_fr1, tum_fr2, tum_fr3, 7scenes, bonn); empty for any other
/// name.
std::string_view embeddedPresetText(std::string_view file);
}  // namespace smap::io::detail
