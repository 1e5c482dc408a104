// smap-segment: segments the frames of a TUM folder or rawlog (every one or every Nth) into
// label images named after each frame, plus colour overlays to look at.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <ostream>
#include <string>
#include <vector>

namespace smap::apps
{
class SegmentApp : public mrpt::system::COutputLogger
{
public:
    SegmentApp();
    /// Arguments after the program name; returns an ExitCode, throws core::InputError.
    int run(const std::vector<std::string>& args, std::ostream& out);
    static std::string usage();
};
}  // namespace smap::apps
