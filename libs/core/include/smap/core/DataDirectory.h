// Where the project's shipped data lies (the segmentation model, the person cut-outs, the sample
// recording, the configuration files): <prefix>/share/semantic-mapper beside the running
// program's <prefix>/bin, or beside the <prefix>/lib of the libraries it links. The build tree has
// the same layout (build/share/semantic-mapper links to the source folders), so a program finds its
// data in the build tree and after `cmake --install` alike; no source-tree path is compiled into a
// binary.
#pragma once

#include <string>

namespace smap::core
{
/// The environment variable that overrides dataDirectory() (e.g. for a program that embeds the
/// mapper and lives outside the prefix).
constexpr const char* kDataDirectoryVariable = "SMAP_DATA_DIR";

/// $SMAP_DATA_DIR when set and not empty; else <folder of the running executable>/../share/
/// semantic-mapper (normalised) when that folder exists; else the same beside the folder of our
/// libraries (<prefix>/lib/../share/semantic-mapper: a program built elsewhere against the
/// installed package finds the data of that installation) when it exists; else the first
/// (where a message about a missing file then points). Empty when no path can be read.
std::string dataDirectory();

/// dataDirectory()/`relative` when it exists (file or folder), else empty.
std::string findDataFile(const std::string& relative);
}  // namespace smap::core
