#include "smap/apps/SynthApp.h"

#include <mrpt/core/format.h>

#include <filesystem>
#include <functional>
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
           "  --scenario S  how the composited people move: random (default; each walks back\n"
           "                and forth), crossing (straight across the view), crowd (3 fast\n"
           "                walkers close in front of the middle frame, filling the view),\n"
           "                seated (in place, swaying), stop_and_stay (walks in, stands 5 s,\n"
           "                walks on, stands again); it sets the default --people-count\n"
           "  --distance-scale F  multiplies how far ahead of the camera the people walk\n"
           "                (default 1; 1.7 puts the crowd on up to about half the view)\n"
           "  --ground-truth F  the colour camera's poses to place the people with (default\n"
           "                TUM_DIR/groundtruth.txt; for 7-Scenes TUM_DIR/groundtruth_sfm.txt,\n"
           "                whose poses are the colour camera's); also the output's ground truth\n"
           "Camera: 640x480, fx = fy = 525, c = (319.5, 239.5); use config/synthetic.ini to read "
           "it.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input.\n";
}

namespace
{
/// The colour camera's poses of a TUM folder's frames, matched by timestamp.
struct PosedFrames
{
    std::string posesPath;
    core::Trajectory gt;
    std::vector<double> frameTimes;             ///< per entry of the folder
    std::vector<core::AssociatedPair> matches;  ///< (entry, pose) in order
};

PosedFrames matchPoses(const CommandLine& cl, const io::TumSource& source,
                       const std::string& folder, double maxDt)
{
    // The poses must be the colour camera's: the frames come on its grid (depth registered to
    // it when the configuration has a [depth_camera]), and a person standing still must stay
    // still against the background seen in colour.
    PosedFrames p;
    p.posesPath = cl.value("ground-truth").value_or(source.groundTruthPath());
    if (p.posesPath.empty())
        throw core::InputError(mrpt::format(
            "'%s' has no groundtruth.txt: compositing needs the camera poses (--ground-truth F)",
            folder.c_str()));
    p.gt = io::readTumTrajectory(p.posesPath);
    std::vector<double> tGt;
    for (const auto& e : source.entries())
        p.frameTimes.push_back(e.rgbTimestamp);
    for (const auto& pose : p.gt)
        tGt.push_back(pose.timestamp);
    p.matches = core::associateTimestamps(p.frameTimes, tGt, maxDt);
    if (p.matches.empty())
        throw core::InputError(mrpt::format("no frame of '%s' has a ground-truth pose within %g s",
                                            folder.c_str(), maxDt));
    return p;
}

/// Up to 8 frames with poses spread over the part used, to see the free space.
std::vector<sim::PeopleCompositor::Probe> collectProbes(io::TumSource& source,
                                                        const PosedFrames& posed, size_t frames)
{
    std::vector<sim::PeopleCompositor::Probe> probes;
    const size_t step = std::max<size_t>(1, frames / 8);
    size_t next = 0, entry = 0;
    while (auto r = source.read())
    {
        const auto* f = std::get_if<core::RgbdFrame>(&*r);
        if (next < frames && entry == posed.matches[next].first)
        {
            if (f != nullptr)  // an unreadable frame is no probe
                probes.push_back({*f, posed.gt[posed.matches[next].second].T_world_cam});
            next += step;
        }
        if (next >= frames)
            break;
        entry++;
    }
    return probes;
}

/// Composite frame i: the real frame of match i with the people at its pose and time.
class CompositeProducer
{
public:
    CompositeProducer(const std::string& folder, const io::FrameSourceParameters& params,
                      const PosedFrames& posed, const sim::PeopleCompositor& compositor)
        : folder_(folder),
          source_(folder, params),
          posed_(posed),
          compositor_(compositor),
          t0_(posed.frameTimes[posed.matches.front().first])
    {
        source_.setMinLoggingLevel(mrpt::system::LVL_WARN);
    }

    sim::SyntheticFrame operator()(size_t i)
    {
        const auto& m = posed_.matches[i];
        std::optional<io::FrameRead> r;
        while (cursor_ <= m.first)
        {
            r = source_.read();
            cursor_++;
        }
        const auto* f = r ? std::get_if<core::RgbdFrame>(&*r) : nullptr;
        if (f == nullptr)  // every composite frame needs its real frame
            throw core::InputError(mrpt::format(
                "--composite-onto: frame %zu of '%s' cannot be read (see the warning above)",
                m.first, folder_.c_str()));
        const auto& T = posed_.gt[m.second].T_world_cam;
        const sim::CompositeFrame c = compositor_.composite(*f, T, f->timestamp - t0_);
        sim::SyntheticFrame out;
        out.index = i;
        out.timestamp = f->timestamp;
        out.T_world_cam = T;
        out.rendered = {c.colour, c.depth, c.labels, c.instances, c.dynamic};
        out.depthNoiseFree = c.depth;
        out.objectPoses = c.objectPoses;
        return out;
    }

private:
    std::string folder_;
    io::TumSource source_;
    const PosedFrames& posed_;
    const sim::PeopleCompositor& compositor_;
    double t0_;
    size_t cursor_ = 0;  ///< next entry index source_ will deliver
};

core::JsonValue compositeMeta(const std::string& folder, const std::string& posesPath,
                              const std::string& peopleDir, long count, uint32_t seed,
                              size_t frames, const sim::PeopleCompositor& compositor,
                              const sim::CompositeLayout& layout)
{
    auto meta = core::JsonValue::object();
    meta.set("generator", "smap-synth").set("mode", "composite").set("source", folder);
    meta.set("poses", posesPath);
    meta.set("people_cutouts", peopleDir).set("people", static_cast<int64_t>(count));
    meta.set("scenario", sim::toString(layout.scenario));
    meta.set("distance_scale", layout.distanceScale);
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
    return meta;
}

/// Composites people into a real TUM folder with ground truth; returns its camera.
core::PinholeCamera compositeOnto(const CommandLine& cl, size_t frames, uint32_t seed,
                                  const std::string& outDir, mrpt::system::COutputLogger& log)
{
    const std::string folder = *cl.value("composite-onto");
    const auto peopleDir = cl.value("people");
    if (!peopleDir)
        throw core::InputError(
            "--composite-onto needs --people CUTOUT_DIR (e.g. ../shared/data/people)");
    sim::CompositeLayout layout;
    layout.scenario = sim::compositeScenarioFromString(cl.value("scenario").value_or("random"));
    layout.distanceScale = cl.number("distance-scale", layout.distanceScale);
    layout.validate();  // before the frames are read
    const long count =
        cl.integer("people-count", static_cast<long>(sim::defaultPeopleCount(layout.scenario)));
    if (count < 1 || count > 8)
        throw core::InputError("--people-count must be 1 .. 8");
    io::FrameSourceParameters params;
    loadAppConfiguration(cl, {&params}, folder, log);

    io::TumSource source(folder, params);
    source.setMinLoggingLevel(log.getMinLoggingLevel());
    const PosedFrames posed = matchPoses(cl, source, folder, params.tum_max_dt);
    frames = std::min(frames, posed.matches.size());
    const auto probes = collectProbes(source, posed, frames);
    std::vector<cv::Mat> sprites;
    for (auto& s : sim::loadPersonSprites(*peopleDir))
        sprites.push_back(std::move(s.image));
    const sim::PeopleCompositor compositor(sprites, posed.gt, probes, static_cast<size_t>(count),
                                           seed, layout);
    if (compositor.freeSpaceViolations() > 0)
        log.logFmt(mrpt::system::LVL_WARN,
                   "compositing: of %zu body samples of the people, %zu lie within 20 cm of an "
                   "observed surface and %zu are seen free by no frame",
                   compositor.freeSpaceCheck().samples, compositor.freeSpaceCheck().inside,
                   compositor.freeSpaceCheck().unseen);
    CompositeProducer produce(folder, params, posed, compositor);
    sim::SyntheticSequenceWriter writer;
    writer.setMinLoggingLevel(log.getMinLoggingLevel());
    writer.write(
        std::ref(produce), frames,
        compositeMeta(folder, posed.posesPath, *peopleDir, count, seed, frames, compositor, layout),
        source.camera(), outDir);
    return source.camera();
}

/// --size WxH: the default camera's field of view at that size.
core::PinholeCamera cameraOfSize(const std::string& size, core::PinholeCamera camera)
{
    int w = 0, h = 0;
    char x = 0;
    std::istringstream ss(size);
    if (!(ss >> w >> x >> h) || x != 'x' || w < 16 || h < 16 || w > 4096 || h > 4096)
        throw core::InputError(
            mrpt::format("--size '%s': expected WxH, e.g. 320x240", size.c_str()));
    camera.fx = camera.fy = 525.0 * w / 640.0;
    camera.cx = (w - 1) / 2.0;
    camera.cy = (h - 1) / 2.0;
    camera.width = w;
    camera.height = h;
    return camera;
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
        .option("scenario")
        .option("distance-scale")
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
        camera = renderPreset(cl, static_cast<size_t>(frames), static_cast<uint32_t>(seed),
                              static_cast<int>(jpeg), *outDir);
        out << "smap-synth: " << frames << " frames of " << *preset << " in " << *outDir << "\n";
    }
    if (!cl.has("no-rawlog"))
        out << "rawlog: " << writeRawlog(*outDir, camera) << "\n";
    if (rows > 0)
    {
        const std::string sheet = (fs::path(*outDir) / "contact_sheet.png").string();
        sim::writeContactSheet(*outDir, static_cast<size_t>(rows), sheet);
        out << "contact sheet: " << sheet << "\n";
    }
    return kExitOk;
}

core::PinholeCamera SynthApp::renderPreset(const CommandLine& cl, size_t frames, uint32_t seed,
                                           int jpegQuality, const std::string& outDir)
{
    if (cl.has("config") || cl.has("set") || cl.has("people") || cl.has("people-count") ||
        cl.has("ground-truth") || cl.has("scenario") || cl.has("distance-scale"))
        throw core::InputError(
            "--config, --set, --people, --people-count, --scenario, --distance-scale and "
            "--ground-truth apply to --composite-onto only");
    sim::GeneratorOptions options;
    if (const auto size = cl.value("size"))
        options.camera = cameraOfSize(*size, options.camera);
    options.preset = *cl.value("preset");
    options.seed = seed;
    options.noiseFreeDepth = cl.has("noise-free");
    sim::SequenceGenerator generator(options);
    MRPT_LOG_INFO_FMT("rendering %zu frames of '%s' (seed %u) into %s", frames,
                      options.preset.c_str(), seed, outDir.c_str());
    sim::SyntheticSequenceWriter writer;
    writer.setMinLoggingLevel(getMinLoggingLevel());
    writer.setColourJpegQuality(jpegQuality);
    writer.write(generator, frames, outDir);
    return options.camera;
}

std::string SynthApp::writeRawlog(const std::string& outDir, const core::PinholeCamera& camera)
{
    io::FrameSourceParameters p;
    p.camera = camera;
    p.tum_depth_factor = sim::SyntheticSequenceWriter::kDepthFactor;
    io::TumSource folder(outDir, p);
    io::TumToRawlogConverter conv("RGBD_SYNTH");
    conv.setMinLoggingLevel(mrpt::system::LVL_WARN);
    return conv.convert(folder, p.tum_depth_factor, (fs::path(outDir) / "sequence.rawlog").string())
        .rawlogPath;
}
}  // namespace smap::apps
