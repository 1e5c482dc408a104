#include "smap/pipeline/SynthApp.h"

#include <mrpt/core/format.h>

#include <filesystem>

#include "smap/core/InputError.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumToRawlogConverter.h"
#include "smap/pipeline/CommandLine.h"
#include "smap/pipeline/SyntheticSequenceWriter.h"

namespace fs = std::filesystem;

namespace smap::pipeline
{
SynthApp::SynthApp() : COutputLogger("smap-synth") {}

std::string SynthApp::usage()
{
    std::string presets;
    for (const auto& p : sim::sequencePresets())
        presets += (presets.empty() ? "" : ", ") + p.name;
    return "Usage: smap-synth --preset NAME --out DIR [--frames N] [--seed S] [--noise-free]\n"
           "                  [--no-rawlog] [--contact-sheet ROWS]\n"
           "\n"
           "Renders a synthetic office with moving people (headless) and writes DIR in TUM RGB-D\n"
           "layout with ground truth: rgb/ depth/ labels/ instances/ dynamic/ objects/,\n"
           "rgb.txt depth.txt associations.txt groundtruth.txt meta.json, plus\n"
           "DIR/sequence.rawlog (+ sequence_Images/) and DIR/contact_sheet.png.\n"
           "  --preset      " +
           presets +
           "\n"
           "  --frames N    number of frames at 30 Hz (default 300)\n"
           "  --seed S      scene, motion and noise seed (default 1); same seed, same output\n"
           "  --noise-free  perfect depth instead of the Kinect-like noise model\n"
           "Camera: 640x480, fx = fy = 525, c = (319.5, 239.5); use config/synthetic.ini to read "
           "it.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input.\n";
}

int SynthApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("preset").option("out").option("frames").option("seed").option("contact-sheet");
    cl.flag("noise-free").flag("no-rawlog").flag("help");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    if (!cl.positionals().empty())
        throw core::InputError("smap-synth takes no positional arguments (see --help)");
    const auto preset = cl.value("preset");
    const auto outDir = cl.value("out");
    if (!preset || !outDir)
        throw core::InputError("smap-synth needs --preset NAME and --out DIR (see --help)");
    const long frames = cl.integer("frames", 300);
    const long seed = cl.integer("seed", 1);
    const long rows = cl.integer("contact-sheet", 6);
    if (frames < 1)
        throw core::InputError(mrpt::format("--frames %ld must be >= 1", frames));
    if (seed < 0 || seed > 0xFFFFFFFFL)
        throw core::InputError(mrpt::format("--seed %ld must be in 0 .. 2^32-1", seed));
    if (rows < 0)
        throw core::InputError("--contact-sheet must be >= 0");

    sim::GeneratorOptions options;
    options.preset = *preset;
    options.seed = static_cast<uint32_t>(seed);
    options.noiseFreeDepth = cl.has("noise-free");
    sim::SequenceGenerator generator(options);
    MRPT_LOG_INFO_FMT("rendering %ld frames of '%s' (seed %ld) into %s", frames, preset->c_str(),
                      seed, outDir->c_str());

    SyntheticSequenceWriter writer;
    writer.setMinLoggingLevel(getMinLoggingLevel());
    writer.write(generator, static_cast<size_t>(frames), *outDir);
    out << "smap-synth: " << frames << " frames of " << *preset << " in " << *outDir << "\n";

    if (!cl.has("no-rawlog"))
    {
        io::FrameSourceParameters p;
        p.camera = options.camera;
        p.tum_depth_factor = SyntheticSequenceWriter::kDepthFactor;
        io::TumSource folder(*outDir, p);
        io::TumToRawlogConverter conv("RGBD_SYNTH");
        conv.setMinLoggingLevel(mrpt::system::LVL_WARN);
        const auto r = conv.convert(folder, p.tum_depth_factor,
                                    (fs::path(*outDir) / "sequence.rawlog").string());
        out << "rawlog: " << r.rawlogPath << "\n";
    }
    if (rows > 0)
    {
        const std::string sheet = (fs::path(*outDir) / "contact_sheet.png").string();
        writeContactSheet(*outDir, static_cast<size_t>(rows), sheet);
        out << "contact sheet: " << sheet << "\n";
    }
    return kExitOk;
}
}  // namespace smap::pipeline
