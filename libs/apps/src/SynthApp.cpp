#include "smap/apps/SynthApp.h"

#include <mrpt/core/format.h>

#include <filesystem>
#include <optional>
#include <sstream>

#include "smap/apps/AppConfiguration.h"
#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"
#include "smap/core/TimestampAssociation.h"
#include "smap/io/TumSource.h"
#include "smap/io/TumTextFormats.h"
#include "smap/io/TumToRawlogConverter.h"
#include "smap/sim/PeopleCompositor.h"
#include "smap/sim/PersonSprite.h"
#include "smap/sim/SyntheticSequenceWriter.h"

namespace fs = std::filesystem;

namespace smap::apps
{
SynthApp::SynthApp() : COutputLogger("smap-synth") {}

std::string SynthApp::usage()
{
    std::string presets;
    for (const auto& p : sim::sequencePresets())
        presets += (presets.empty() ? "" : ", ") + p.name;
    return "Usage: smap-synth --preset NAME --out DIR [--frames N] [--seed S] [--noise-free]\n"
           "                  [--no-rawlog] [--contact-sheet ROWS]\n"
           "       smap-synth --composite-onto TUM_DIR --people CUTOUT_DIR --out DIR [--config F]\n"
           "                  [--set S.K=V]... [--ground-truth F] [--people-count N] [--frames N]\n"
           "                  [--seed S] ...\n"
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
           "  --size WxH    image size (default 640x480; the field of view stays the same)\n"
           "  --jpeg-quality Q  colour as JPEG of quality Q instead of PNG (smaller samples)\n"
           "  --composite-onto TUM_DIR  instead of rendering, walk people cut-outs (--people DIR,\n"
           "                --people-count N, default 2) through a real TUM folder with\n"
           "                groundtruth.txt; --config/--set give its camera and depth factor.\n"
           "                The output is in the colour camera's geometry (depth registered to\n"
           "                it when the camera preset has a [depth_camera], as 7scenes.ini does)\n"
           "  --ground-truth F  the colour camera's poses to place the people with (default\n"
           "                TUM_DIR/groundtruth.txt; for 7-Scenes TUM_DIR/groundtruth_sfm.txt,\n"
           "                whose poses are the colour camera's); also the output's ground truth\n"
           "Camera: 640x480, fx = fy = 525, c = (319.5, 239.5); use config/synthetic.ini to read "
           "it.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input.\n";
}

namespace
{
/// Composites people into a real TUM folder with ground truth; returns its camera.
core::PinholeCamera compositeOnto(const CommandLine& cl, size_t frames, uint32_t seed,
                                  const std::string& outDir, mrpt::system::COutputLogger& log)
{
    const std::string folder = *cl.value("composite-onto");
    const auto peopleDir = cl.value("people");
    if (!peopleDir)
        throw core::InputError(
            "--composite-onto needs --people CUTOUT_DIR (e.g. ../shared/data/people)");
    const long count = cl.integer("people-count", 2);
    if (count < 1 || count > 8)
        throw core::InputError("--people-count must be 1 .. 8");
    io::FrameSourceParameters params;
    loadAppConfiguration(cl, {&params}, folder, log);

    io::TumSource source(folder, params);
    source.setMinLoggingLevel(log.getMinLoggingLevel());
    // The poses must be the colour camera's: the frames come on its grid (depth registered to
    // it when the configuration has a [depth_camera]), and a person standing still must stay
    // still against the background seen in colour.
    const std::string posesPath = cl.value("ground-truth").value_or(source.groundTruthPath());
    if (posesPath.empty())
        throw core::InputError(mrpt::format(
            "'%s' has no groundtruth.txt: compositing needs the camera poses (--ground-truth F)",
            folder.c_str()));
    const core::Trajectory gt = io::readTumTrajectory(posesPath);
    std::vector<double> tFrames, tGt;
    for (const auto& e : source.entries())
        tFrames.push_back(e.rgbTimestamp);
    for (const auto& p : gt)
        tGt.push_back(p.timestamp);
    const auto matches = core::associateTimestamps(tFrames, tGt, params.tum_max_dt);
    if (matches.empty())
        throw core::InputError(mrpt::format("no frame of '%s' has a ground-truth pose within %g s",
                                            folder.c_str(), params.tum_max_dt));
    frames = std::min(frames, matches.size());

    // Probes: up to 8 frames with poses spread over the part used, to see the free space.
    std::vector<sim::PeopleCompositor::Probe> probes;
    {
        const size_t step = std::max<size_t>(1, frames / 8);
        size_t next = 0, entry = 0;
        while (auto r = source.read())
        {
            const auto* f = std::get_if<core::RgbdFrame>(&*r);
            if (next < frames && entry == matches[next].first)
            {
                if (f != nullptr)  // an unreadable frame is no probe
                    probes.push_back({*f, gt[matches[next].second].T_world_cam});
                next += step;
            }
            if (next >= frames)
                break;
            entry++;
        }
    }
    std::vector<cv::Mat> sprites;
    for (auto& s : sim::loadPersonSprites(*peopleDir))
        sprites.push_back(std::move(s.image));
    const sim::PeopleCompositor compositor(sprites, gt, probes, static_cast<size_t>(count), seed);
    if (compositor.freeSpaceViolations() > 0)
        log.logFmt(mrpt::system::LVL_WARN,
                   "compositing: of %zu body samples of the people, %zu lie within 20 cm of an "
                   "observed surface and %zu are seen free by no frame",
                   compositor.freeSpaceCheck().samples, compositor.freeSpaceCheck().inside,
                   compositor.freeSpaceCheck().unseen);
    io::TumSource frameSource(folder, params);
    frameSource.setMinLoggingLevel(mrpt::system::LVL_WARN);
    size_t cursor = 0;  // next entry index frameSource will deliver
    const double t0 = tFrames[matches.front().first];
    auto produce = [&](size_t i)
    {
        const auto& m = matches[i];
        std::optional<io::FrameRead> r;
        while (cursor <= m.first)
        {
            r = frameSource.read();
            cursor++;
        }
        const auto* f = r ? std::get_if<core::RgbdFrame>(&*r) : nullptr;
        if (f == nullptr)  // every composite frame needs its real frame
            throw core::InputError(mrpt::format(
                "--composite-onto: frame %zu of '%s' cannot be read (see the warning above)",
                m.first, folder.c_str()));
        const auto& T = gt[m.second].T_world_cam;
        const sim::CompositeFrame c = compositor.composite(*f, T, f->timestamp - t0);
        sim::SyntheticFrame out;
        out.index = i;
        out.timestamp = f->timestamp;
        out.T_world_cam = T;
        out.rendered = {c.colour, c.depth, c.labels, c.instances, c.dynamic};
        out.depthNoiseFree = c.depth;
        out.objectPoses = c.objectPoses;
        return out;
    };
    auto meta = core::JsonValue::object();
    meta.set("generator", "smap-synth").set("mode", "composite").set("source", folder);
    meta.set("poses", posesPath);
    meta.set("people_cutouts", *peopleDir).set("people", static_cast<int64_t>(count));
    meta.set("seed", static_cast<int64_t>(seed)).set("frames", static_cast<uint64_t>(frames));
    meta.set("depth_factor", sim::SyntheticSequenceWriter::kDepthFactor);
    meta.set("floor_height_m", compositor.floorHeight());
    const auto& fsc = compositor.freeSpaceCheck();
    auto freeSpace = core::JsonValue::object();
    freeSpace.set("body_samples", static_cast<uint64_t>(fsc.samples));
    freeSpace.set("inside_observed_surface", static_cast<uint64_t>(fsc.inside));
    freeSpace.set("never_seen_free", static_cast<uint64_t>(fsc.unseen));
    meta.set("free_space_check", freeSpace);
    auto up = core::JsonValue::array();
    for (int k = 0; k < 3; k++)
        up.push(core::JsonValue::number(compositor.up()[k]));
    meta.set("world_up", up);
    meta.set("labels",
             "15 person where composited, 255 unknown elsewhere; depth of people is exact, the "
             "rest is the real sensor's");
    sim::SyntheticSequenceWriter writer;
    writer.setMinLoggingLevel(log.getMinLoggingLevel());
    writer.write(produce, frames, meta, source.camera(), outDir);
    return source.camera();
}
}  // namespace

int SynthApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("preset").option("out").option("frames").option("seed").option("contact-sheet");
    cl.option("composite-onto")
        .option("ground-truth")
        .option("people")
        .option("people-count")
        .option("config")
        .option("set");
    cl.option("size").option("jpeg-quality");
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
    const bool composite = cl.has("composite-onto");
    if (!outDir || preset.has_value() == composite)
        throw core::InputError(
            "smap-synth needs --out DIR and either --preset NAME or --composite-onto TUM_DIR (see "
            "--help)");
    const long frames = cl.integer("frames", 300);
    const long seed = cl.integer("seed", 1);
    const long rows = cl.integer("contact-sheet", 6);
    if (frames < 1)
        throw core::InputError(mrpt::format("--frames %ld must be >= 1", frames));
    if (seed < 0 || seed > 0xFFFFFFFFL)
        throw core::InputError(mrpt::format("--seed %ld must be in 0 .. 2^32-1", seed));
    if (rows < 0)
        throw core::InputError("--contact-sheet must be >= 0");
    const long jpeg = cl.integer("jpeg-quality", 0);
    if (jpeg < 0 || jpeg > 100)
        throw core::InputError("--jpeg-quality must be 1 .. 100 (0 = PNG)");

    core::PinholeCamera camera;
    if (composite)
    {
        if (cl.has("size") || cl.has("preset") || cl.has("noise-free"))
            throw core::InputError("--size and --noise-free apply to rendered presets only");
        camera = compositeOnto(cl, static_cast<size_t>(frames), static_cast<uint32_t>(seed),
                               *outDir, *this);
        out << "smap-synth: people composited onto " << *cl.value("composite-onto") << " in "
            << *outDir << "\n";
    }
    else
    {
        if (cl.has("config") || cl.has("set") || cl.has("people") || cl.has("people-count") ||
            cl.has("ground-truth"))
            throw core::InputError(
                "--config, --set, --people, --people-count and --ground-truth apply to "
                "--composite-onto only");
        sim::GeneratorOptions options;
        if (const auto size = cl.value("size"))
        {
            int w = 0, h = 0;
            char x = 0;
            std::istringstream ss(*size);
            if (!(ss >> w >> x >> h) || x != 'x' || w < 16 || h < 16 || w > 4096 || h > 4096)
                throw core::InputError(
                    mrpt::format("--size '%s': expected WxH, e.g. 320x240", size->c_str()));
            // Same field of view as the 640x480 default.
            options.camera.fx = options.camera.fy = 525.0 * w / 640.0;
            options.camera.cx = (w - 1) / 2.0;
            options.camera.cy = (h - 1) / 2.0;
            options.camera.width = w;
            options.camera.height = h;
        }
        options.preset = *preset;
        options.seed = static_cast<uint32_t>(seed);
        options.noiseFreeDepth = cl.has("noise-free");
        sim::SequenceGenerator generator(options);
        MRPT_LOG_INFO_FMT("rendering %ld frames of '%s' (seed %ld) into %s", frames,
                          preset->c_str(), seed, outDir->c_str());
        sim::SyntheticSequenceWriter writer;
        writer.setMinLoggingLevel(getMinLoggingLevel());
        writer.setColourJpegQuality(static_cast<int>(jpeg));
        writer.write(generator, static_cast<size_t>(frames), *outDir);
        camera = options.camera;
        out << "smap-synth: " << frames << " frames of " << *preset << " in " << *outDir << "\n";
    }

    if (!cl.has("no-rawlog"))
    {
        io::FrameSourceParameters p;
        p.camera = camera;
        p.tum_depth_factor = sim::SyntheticSequenceWriter::kDepthFactor;
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
        sim::writeContactSheet(*outDir, static_cast<size_t>(rows), sheet);
        out << "contact sheet: " << sheet << "\n";
    }
    return kExitOk;
}
}  // namespace smap::apps
