#include "smap/apps/SegmentApp.h"

#include <mrpt/core/format.h>
#include <mrpt/system/CTicTac.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "smap/apps/AppConfiguration.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/JsonWriter.h"
#include "smap/core/Median.h"
#include "smap/core/OutputDirectory.h"
#include "smap/io/FrameSource.h"
#include "smap/segmentation/SegmentationParameters.h"

namespace fs = std::filesystem;

namespace smap::apps
{
namespace
{
void writeImage(const fs::path& path, const cv::Mat& img)
{
    core::writeFileAtomically(path.string(),
                              [&](const std::string& tmp)
                              {
                                  if (!cv::imwrite(tmp, img))
                                      throw std::runtime_error("cannot write " + path.string());
                              });
}

using core::upperMedian;
}  // namespace

SegmentApp::SegmentApp() : COutputLogger("smap-segment") {}

std::string SegmentApp::usage()
{
    return "Usage: smap-segment --config FILE [--config FILE]... INPUT OUTDIR [--every N]\n"
           "                    [--max-frames N] [--set section.key=value]... [--no-overlay]\n"
           "\n"
           "Segments the frames of INPUT (a TUM RGB-D folder or an MRPT rawlog) with the\n"
           "configured segmenter ([segmentation], [onnx], [label_images], [crf]; e.g.\n"
           "config/espnetv2_voc.ini) and writes, per frame:\n"
           "  OUTDIR/<stem>.png          8-bit label image (class ids, PASCAL VOC by default),\n"
           "                             <stem> = the input colour image's file stem\n"
           "  OUTDIR/overlay/<stem>.png  the colour image with the labels blended in\n"
           "and OUTDIR/segmentation.json (segmenter, frames, median time per frame).\n"
           "Several --config files apply in order (a camera preset, then the segmenter), e.g.\n"
           "  smap-segment --config config/7scenes.ini --config config/espnetv2_voc.ini \\\n"
           "      ../shared/data/7scenes-redkitchen out/kitchen-labels --every 10\n"
           "  --every N       segment every Nth frame (default 1)\n"
           "  --max-frames N  stop after N input frames (default: all)\n"
           "  --no-overlay    label images only\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input.\n";
}

int SegmentApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("config").option("set").option("every").option("max-frames");
    cl.flag("no-overlay").flag("help");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    if (cl.positionals().size() != 2)
        throw core::InputError("expected 'smap-segment --config FILE INPUT OUTDIR' (see --help)");
    const long every = cl.integer("every", 1);
    const long maxFrames = cl.integer("max-frames", 0);
    if (every < 1 || maxFrames < 0)
        throw core::InputError("--every must be >= 1 and --max-frames >= 0");

    io::FrameSourceParameters sourceParams;
    segmentation::SegmentationParameters segParams;
    loadAppConfiguration(cl, {&sourceParams, &segParams}, cl.positionals()[0], *this);
    sourceParams.stride *= static_cast<size_t>(every);
    if (maxFrames > 0)
        sourceParams.max_frames = static_cast<size_t>(maxFrames);

    if (!segmentation::useShippedModelIfUnset(segParams))
        throw core::InputError("no [onnx] model configured and the shipped model " +
                               segmentation::shippedModelPath() + " does not exist");
    auto segmenter = segmentation::makeSegmenter(segParams);
    if (!segmenter)
        throw core::InputError(
            "smap-segment needs a segmentation backend ([segmentation] "
            "backend = none segments nothing)");
    segmenter->setMinLoggingLevel(getMinLoggingLevel());
    auto source = io::openFrameSource(cl.positionals()[0], sourceParams);
    source->setMinLoggingLevel(getMinLoggingLevel());
    const fs::path outDir = cl.positionals()[1];
    const bool overlay = !cl.has("no-overlay");
    core::prepareOutputDirectory(outDir.string(), "OUT_DIR");
    if (overlay)
        fs::create_directories(outDir / "overlay");
    MRPT_LOG_INFO_FMT("%s -> %s with %s", source->description().c_str(), outDir.string().c_str(),
                      segmenter->description().c_str());

    std::vector<double> times;
    const auto total = source->sizeHint();
    mrpt::system::CTicTac clock;
    while (auto frame = source->next())
    {
        mrpt::system::CTicTac t;
        const auto r = segmenter->segment(*frame);
        times.push_back(1e3 * t.Tac());
        writeImage(outDir / (frame->name + ".png"), r.labels);
        if (overlay)
            writeImage(outDir / "overlay" / (frame->name + ".png"),
                       segmenter->labels().overlay(frame->colour, r.labels));
        if (times.size() % 25 == 0)
            MRPT_LOG_INFO_FMT("%zu%s frames segmented, %.1f frames/s", times.size(),
                              total ? mrpt::format(" of %zu", *total).c_str() : "",
                              static_cast<double>(times.size()) / clock.Tac());
    }
    if (times.empty())
        throw core::InputError("'" + cl.positionals()[0] + "' has no frames to segment");

    auto j = core::JsonValue::object();
    j.set("input", cl.positionals()[0])
        .set("segmenter", segmenter->description())
        .set("frames", static_cast<uint64_t>(times.size()))
        .set("every", static_cast<int64_t>(every))
        .set("median_ms_per_frame", upperMedian(times));
    core::AtomicTextFile f((outDir / "segmentation.json").string());
    f.stream() << j.dump();
    f.commit();
    out << mrpt::format("smap-segment: %zu frames -> %s (median %.1f ms per frame, %s)\n",
                        times.size(), outDir.string().c_str(), upperMedian(times),
                        segmenter->description().c_str());
    return kExitOk;
}
}  // namespace smap::apps
