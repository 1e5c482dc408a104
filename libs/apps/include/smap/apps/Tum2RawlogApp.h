// tum2rawlog: converts a TUM RGB-D folder into an MRPT rawlog that RawLogViewer opens.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <ostream>
#include <string>
#include <vector>

namespace smap::apps
{
class Tum2RawlogApp : public mrpt::system::COutputLogger
{
public:
    Tum2RawlogApp();
    /// Arguments after the program name; returns an ExitCode, throws core::InputError.
    int run(const std::vector<std::string>& args, std::ostream& out);
    static std::string usage();
};
}  // namespace smap::apps
