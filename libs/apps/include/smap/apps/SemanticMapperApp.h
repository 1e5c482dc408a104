// The semantic-mapper command: an RGB-D recording in; trajectory, semantic maps, snapshots,
// an annotated rawlog and metrics out (README.md, docs/pipeline.md "Outputs").
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <ostream>
#include <string>
#include <vector>

namespace smap::apps
{
class SemanticMapperApp : public mrpt::system::COutputLogger
{
public:
    struct Result
    {
        size_t frames = 0;
        size_t keyframes = 0;
        bool interrupted = false;
        std::string outputDirectory;
        std::string input;
    };

    SemanticMapperApp();

    /// Runs with the arguments after the program name. Returns an ExitCode (kExitInterrupted
    /// after Ctrl-C, with complete outputs for the frames processed); throws core::InputError
    /// for bad arguments, configuration or data. `progress`: where the in-place progress line
    /// goes when it is a terminal (null: log lines).
    int run(const std::vector<std::string>& args, std::ostream& out,
            std::ostream* progress = nullptr);
    const Result& result() const { return result_; }

    static std::string usage();
    /// The embedded default recording used when no INPUT is given: the sample in the data
    /// folder (core::dataDirectory()), or empty when it is not there.
    static std::string defaultInput();
    /// Every configuration key with its default and the comment of its section, as an INI
    /// file (docs/config-reference.ini is generated from it).
    static std::string configurationReference();

private:
    Result result_;
};
}  // namespace smap::apps
