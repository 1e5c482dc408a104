// The folder an app writes into, checked before any work starts: a wrong --out (an existing
// file, a read-only place) is the user's to fix, said in one line, not an internal error found
// after minutes of processing.
#pragma once

#include <string>

namespace smap::core
{
/// Creates `dir` (and its parents) if needed and checks that a file can be created in it.
/// Throws InputError naming `dir`, `option` (e.g. "--out") and the system's reason.
void prepareOutputDirectory(const std::string& dir, const std::string& option);
}  // namespace smap::core
