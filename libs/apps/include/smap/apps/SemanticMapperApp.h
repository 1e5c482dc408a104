// The semantic-mapper command: an RGB-D recording in; trajectory, semantic maps, snapshots,
// an annotated rawlog and metrics out (README.md, docs/pipeline.md "Outputs").
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "smap/apps/FrameSelection.h"
#include "smap/io/FrameSourceParameters.h"
#include "smap/pipeline/SemanticMapperParameters.h"

namespace smap::apps
{
class CommandLine;
class InterruptWatcher;
namespace detail
{
struct MapperRun;  ///< one run's state, handed from step to step
}

/// As MRPT's mrpt-apps classes: initialize() reads the command line and the configuration into
/// the public members, which a caller may still edit, then run() processes the recording and
/// leaves its summary in result().
class SemanticMapperApp : public mrpt::system::COutputLogger
{
public:
    /// What the command line chose besides the configuration.
    struct Options
    {
        std::string input;                         ///< rawlog or TUM folder
        std::string outputDirectory = "smap-out";  ///< --out
        std::vector<std::string> groundTruths;     ///< --gt; empty: the input's references
        std::string groundTruthLabels;             ///< --gt-labels; empty: found beside input
        int groundTruthVoid = 255;                 ///< --gt-void; -1 = none
        FrameSelection debugFrames;                ///< --dynamic-debug
    };
    struct Result
    {
        size_t frames = 0;
        size_t keyframes = 0;
        bool interrupted = false;
        std::string outputDirectory;
        std::string input;
    };

    SemanticMapperApp();
    ~SemanticMapperApp() override;

    /// Parses the arguments after the program name and loads the configuration (files, then
    /// --set) into options, sourceParameters and parameters. Returns false when the command
    /// only printed something (--help, --print-config). Throws core::InputError for bad
    /// arguments or configuration.
    bool initialize(const std::vector<std::string>& args, std::ostream& out);
    /// Processes options.input with the parameters. Returns an ExitCode (kExitInterrupted after
    /// Ctrl-C, with complete outputs for the frames processed); throws core::InputError for bad
    /// data. `progress`: where the in-place progress line goes when it is a terminal (null: log
    /// lines).
    int run(std::ostream& out, std::ostream* progress = nullptr);
    /// initialize(), then run() unless there is nothing to run: the command line.
    int run(const std::vector<std::string>& args, std::ostream& out,
            std::ostream* progress = nullptr);
    const Result& result() const { return result_; }

    Options options;
    io::FrameSourceParameters sourceParameters;
    pipeline::SemanticMapperParameters parameters;

    static std::string usage();
    /// The embedded default recording used when no INPUT is given: the sample in the data
    /// folder (core::dataDirectory()), or empty when it is not there.
    static std::string defaultInput();
    /// Every configuration key with its default and the comment of its section, as an INI
    /// file (docs/config-reference.ini is generated from it).
    static std::string configurationReference();

private:
    void parseGroundTruthOptions(const CommandLine& cl);
    void chooseSegmenter();
    void openInput(detail::MapperRun& s) const;
    void startMapper(detail::MapperRun& s) const;
    void writeEffectiveConfiguration(detail::MapperRun& s) const;
    void attachKeyFrameOutputs(detail::MapperRun& s) const;
    void trackAllFrames(detail::MapperRun& s, const InterruptWatcher& interrupt,
                        std::ostream* progress);
    void finishMapping(detail::MapperRun& s);
    void writeMapOutputs(detail::MapperRun& s) const;
    void writeMetrics(detail::MapperRun& s);
    void reportSummary(const detail::MapperRun& s, std::ostream& out);
    void checkSkippedFraction(const detail::MapperRun& s) const;

    Result result_;
};
}  // namespace smap::apps
