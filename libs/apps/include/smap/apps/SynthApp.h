// smap-synth: writes a synthetic RGB-D sequence with full ground truth (TUM layout + labels,
// instances, dynamic masks, object trajectories, meta.json), its rawlog, and a contact sheet.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <ostream>
#include <string>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::apps
{
class CommandLine;

class SynthApp : public mrpt::system::COutputLogger
{
public:
    SynthApp();
    /// Arguments after the program name; returns an ExitCode, throws core::InputError.
    int run(const std::vector<std::string>& args, std::ostream& out);
    static std::string usage();

private:
    /// A rendered preset (--preset) into outDir; returns its camera.
    core::PinholeCamera renderPreset(const CommandLine& cl, size_t frames, uint32_t seed,
                                     int jpegQuality, const std::string& outDir);
    /// OUT/sequence.rawlog from the folder just written; returns its path.
    static std::string writeRawlog(const std::string& outDir, const core::PinholeCamera& camera);
};
}  // namespace smap::apps
