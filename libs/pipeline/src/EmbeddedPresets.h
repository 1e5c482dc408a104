// The text of the camera presets in config/, compiled in (EmbeddedPresets.cpp is generated from
// the .ini files by CMake).
#pragma once

#include <string_view>

namespace smap::pipeline::detail
{
/// INI text of config/<file> ("tum_fr1.ini", "tum_fr2.ini", "tum_fr3.ini", "7scenes.ini") as it
/// was at build time; empty for any other name.
std::string_view embeddedPresetText(std::string_view file);
}  // namespace smap::pipeline::detail
