// The semantic-mapper command: reads an RGB-D recording and writes its outputs to a folder.
// Stages land one by one; today it reads and decodes every frame and writes a summary of them.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <ostream>
#include <string>
#include <vector>

namespace smap::pipeline
{
class SemanticMapperApp : public mrpt::system::COutputLogger
{
public:
    struct Result
    {
        size_t frames = 0;
        std::string outputDirectory;
        std::string input;
    };

    SemanticMapperApp();

    /// Runs with the arguments after the program name. Returns an ExitCode; throws
    /// core::InputError for bad arguments, configuration or data.
    int run(const std::vector<std::string>& args, std::ostream& out);
    const Result& result() const { return result_; }

    static std::string usage();
    /// The embedded default recording used when no INPUT is given.
    static std::string defaultInput();

private:
    Result result_;
};
}  // namespace smap::pipeline
