// Configuration of an app run: every --config FILE in order, then every --set section.key=value,
// loaded into all of the app's parameter structs at once so that unknown keys are caught before any
// work.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <vector>

#include "smap/pipeline/CommandLine.h"

namespace smap::pipeline
{
/// Throws core::InputError naming the file and key for unreadable files, bad values and keys
/// that none of `params` reads.
void loadAppConfiguration(const CommandLine& cl,
                          const std::vector<mrpt::config::CLoadableOptions*>& params);
}  // namespace smap::pipeline
