// Configuration of an app run: every --config FILE in order, then every --set section.key=value,
// loaded into all of the app's parameter structs at once so that unknown keys are caught before any
// work.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/system/COutputLogger.h>

#include <string>
#include <vector>

#include "smap/apps/CommandLine.h"
#include "smap/segmentation/SegmentationParameters.h"

namespace smap::apps
{
/// Throws core::InputError naming the file and key for unreadable files, bad values and keys
/// that none of `params` reads.
///
/// `input` is the recording the app will read: when the configuration has no [camera] and
/// `input` is a folder with a preset of its own (io::presetForInput: its camera.ini, or the dataset
/// its name names), that preset is loaded first, under the files and overrides, and `log` says
/// so at INFO level.
void loadAppConfiguration(const CommandLine& cl,
                          const std::vector<mrpt::config::CLoadableOptions*>& params,
                          const std::string& input, mrpt::system::COutputLogger& log);

}  // namespace smap::apps
