#include "smap/apps/Tum2RawlogApp.h"

#include "smap/apps/AppConfiguration.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumToRawlogConverter.h"

namespace smap::apps
{
Tum2RawlogApp::Tum2RawlogApp() : COutputLogger("tum2rawlog") {}

std::string Tum2RawlogApp::usage()
{
    return "Usage: tum2rawlog TUM_FOLDER OUTPUT.rawlog [--config FILE] [--set "
           "section.key=value]...\n"
           "                  [--sensor-label LABEL] [--max-frames N]\n"
           "\n"
           "Writes OUTPUT.rawlog (CObservation3DRangeScan per rgb/depth pair), OUTPUT_Images/\n"
           "(colour files copied, depth as MRPT .bin range images) and, when the folder has\n"
           "groundtruth.txt, OUTPUT_groundtruth.txt. Camera and depth factor come from the\n"
           "configuration's [camera] and [tum] sections, e.g. --config config/7scenes.ini.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input.\n";
}

int Tum2RawlogApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("config").option("set").option("sensor-label").option("max-frames").flag("help");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    if (cl.positionals().size() != 2)
        throw core::InputError("expected 'tum2rawlog TUM_FOLDER OUTPUT.rawlog' (see --help)");
    const long maxFrames = cl.integer("max-frames", 0);
    if (maxFrames < 0)
        throw core::InputError("--max-frames must be >= 0");

    io::FrameSourceParameters params;
    loadAppConfiguration(cl, {&params}, cl.positionals()[0], *this);

    io::TumSource source(cl.positionals()[0], params);
    source.setMinLoggingLevel(getMinLoggingLevel());
    io::TumToRawlogConverter converter(cl.value("sensor-label").value_or("RGBD"));
    converter.setMinLoggingLevel(getMinLoggingLevel());
    const auto r = converter.convert(source, params.tum_depth_factor, cl.positionals()[1],
                                     static_cast<size_t>(maxFrames));
    out << "tum2rawlog: " << r.frames << " frames -> " << r.rawlogPath << " (images in "
        << r.imagesDirectory << ")\n";
    if (!r.groundTruthPath.empty())
        out << "ground truth -> " << r.groundTruthPath << "\n";
    return kExitOk;
}
}  // namespace smap::apps
