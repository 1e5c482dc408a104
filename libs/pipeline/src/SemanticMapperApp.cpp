#include "smap/pipeline/SemanticMapperApp.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/system/CTicTac.h>

#include <filesystem>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/JsonWriter.h"
#include "smap/io/FrameSource.h"
#include "smap/pipeline/AppConfiguration.h"
#include "smap/pipeline/CommandLine.h"
#include "smap/pipeline/FrameSummary.h"

namespace fs = std::filesystem;

namespace smap::pipeline
{
SemanticMapperApp::SemanticMapperApp() : COutputLogger("semantic-mapper") {}

std::string SemanticMapperApp::defaultInput()
{
#ifdef SMAP_DEFAULT_INPUT
    return SMAP_DEFAULT_INPUT;
#else
    return {};
#endif
}

std::string SemanticMapperApp::usage()
{
    return "Usage: semantic-mapper [INPUT] [--config FILE] [--out DIR] [--set "
           "section.key=value]...\n"
           "\n"
           "  INPUT        an MRPT .rawlog (plain or gzip) or a TUM RGB-D folder;\n"
           "               default: the embedded sample " +
           defaultInput() +
           "\n"
           "  --config F   INI or YAML configuration (see config/ and docs/configuration.md)\n"
           "  --out DIR    output folder (default: smap-out)\n"
           "  --set S.K=V  override one configuration key, e.g. --set input.max_frames=100\n"
           "  --quiet      only warnings and errors\n"
           "  --help       this text\n"
           "\n"
           "Outputs in DIR: summary.json, frames.csv, config-effective.ini.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input (arguments, configuration, data).\n";
}

int SemanticMapperApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("config").option("out").option("set").flag("help").flag("quiet");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    if (cl.has("quiet"))
        setMinLoggingLevel(mrpt::system::LVL_WARN);
    if (cl.positionals().size() > 1)
        throw core::InputError("semantic-mapper takes at most one INPUT (see --help)");

    std::string input = cl.positionals().empty() ? defaultInput() : cl.positionals()[0];
    if (input.empty())
        throw core::InputError(
            "no INPUT given and no embedded default recording was found at build time");
    const std::string outDir = cl.value("out").value_or("smap-out");

    // Configuration: file, then --set overrides; every component loads its parameters once.
    io::FrameSourceParameters sourceParams;
    loadAppConfiguration(cl, {&sourceParams});

    auto source = io::openFrameSource(input, sourceParams);
    source->setMinLoggingLevel(getMinLoggingLevel());
    fs::create_directories(outDir);
    MRPT_LOG_INFO_STREAM("reading " << source->description() << " -> " << outDir);

    {
        mrpt::config::CConfigFileMemory effective;
        sourceParams.saveToConfigFile(effective, "");
        core::AtomicTextFile f((fs::path(outDir) / "config-effective.ini").string());
        f.stream() << "# effective configuration of semantic-mapper (defaults, --config, --set)\n"
                   << effective.getContent();
        f.commit();
    }

    core::AtomicTextFile csv((fs::path(outDir) / "frames.csv").string());
    csv.stream() << frameStatsCsvHeader() << "\n";
    mrpt::system::CTicTac timer;
    double lastReport = 0.0, sumValid = 0.0;
    const auto total = source->sizeHint();
    size_t n = 0;
    double firstStamp = 0.0, lastStamp = 0.0;
    core::PinholeCamera camera;
    while (auto frame = source->next())
    {
        frame->validate();
        const FrameStats s = computeFrameStats(*frame);
        csv.stream() << toCsvRow(s) << "\n";
        if (n == 0)
        {
            firstStamp = frame->timestamp;
            camera = frame->camera;
        }
        lastStamp = frame->timestamp;
        sumValid += s.validDepthFraction;
        n++;
        const double t = timer.Tac();
        if (t - lastReport > 2.0)
        {
            lastReport = t;
            const double fps = n / t;
            if (total)
                MRPT_LOG_INFO_FMT("frame %zu / %zu  %.1f frames/s  ETA %.0f s", n, *total, fps,
                                  (*total - n) / fps);
            else
                MRPT_LOG_INFO_FMT("frame %zu  %.1f frames/s", n, fps);
        }
    }
    csv.commit();
    const double elapsed = timer.Tac();

    auto cam = core::JsonValue::object();
    cam.set("width", camera.width)
        .set("height", camera.height)
        .set("fx", camera.fx)
        .set("fy", camera.fy);
    cam.set("cx", camera.cx).set("cy", camera.cy);
    auto dist = core::JsonValue::array();
    for (double d : camera.distortion)
        dist.push(core::JsonValue::number(d));
    cam.set("distortion_k1_k2_p1_p2_k3", dist);
    auto summary = core::JsonValue::object();
    summary.set("input", fs::absolute(input).string()).set("source", source->description());
    summary.set("frames", static_cast<uint64_t>(n));
    summary.set("first_timestamp", firstStamp).set("last_timestamp", lastStamp);
    summary.set("duration_s", lastStamp - firstStamp);
    summary.set("mean_valid_depth_fraction", n ? sumValid / n : 0.0);
    summary.set("camera", cam);
    summary.set("ground_truth", source->groundTruthPath());
    summary.set("processing_time_s", elapsed)
        .set("frames_per_second", elapsed > 0 ? n / elapsed : 0.0);
    {
        core::AtomicTextFile f((fs::path(outDir) / "summary.json").string());
        f.stream() << summary.dump();
        f.commit();
    }

    result_ = {n, outDir, input};
    MRPT_LOG_INFO_FMT("%zu frames in %.2f s (%.1f frames/s)", n, elapsed,
                      elapsed > 0 ? n / elapsed : 0.0);
    out << "semantic-mapper: " << n << " frames from " << input << "\n"
        << "outputs in " << fs::absolute(outDir).string()
        << "/: summary.json, frames.csv, config-effective.ini\n";
    return kExitOk;
}
}  // namespace smap::pipeline
