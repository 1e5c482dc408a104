#include "smap/apps/SemanticMapperApp.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <thread>

#include "smap/apps/AppConfiguration.h"
#include "smap/apps/CommandLine.h"
#include "smap/apps/FrameSelection.h"
#include "smap/apps/InterruptWatcher.h"
#include "smap/apps/KeyFrameScorer.h"
#include "smap/apps/ProgressReporter.h"
#include "smap/apps/RunLog.h"
#include "smap/core/AtomicFile.h"
#include "smap/core/DataDirectory.h"
#include "smap/core/Elapsed.h"
#include "smap/core/InputError.h"
#include "smap/core/JsonWriter.h"
#include "smap/core/OutputDirectory.h"
#include "smap/dynamic/EvidenceReport.h"
#include "smap/eval/AbsoluteTrajectoryError.h"
#include "smap/eval/EvalReport.h"
#include "smap/eval/RelativePoseError.h"
#include "smap/eval/TrajectoryPlot.h"
#include "smap/io/FrameSource.h"
#include "smap/io/RawlogWriter.h"
#include "smap/io/TumTextFormats.h"
#include "smap/pipeline/BoundedQueue.h"
#include "smap/pipeline/FrameFeeder.h"
#include "smap/pipeline/FrameSummary.h"
#include "smap/pipeline/MapOutputWriter.h"
#include "smap/pipeline/SemanticMapper.h"

namespace fs = std::filesystem;

namespace smap::apps
{
namespace
{
/// DIR/dynamic/NNNNNN.png (the paper's Figure 4 style) and .csv (evidence per keypoint).
void writeDynamicDebug(const std::string& outDir, size_t index,
                       const pipeline::SemanticMapper::PreparedFrame& p)
{
    const fs::path dir = fs::path(outDir) / "dynamic";
    fs::create_directories(dir);
    const std::string stem = (dir / mrpt::format("%06zu", index)).string();
    const cv::Mat picture = dynamic::drawEvidence(p.rgbd.colour, p.features.features, p.dynamic);
    core::writeFileAtomically(stem + ".png",
                              [&](const std::string& tmp)
                              {
                                  if (!cv::imwrite(tmp, picture))
                                      throw std::runtime_error("cannot write " + stem + ".png");
                              });
    core::AtomicTextFile csv(stem + ".csv");
    csv.stream() << dynamic::evidenceCsv(p.features.features, p.dynamic);
    csv.commit();
}

/// ATE and RPE (1 s) of `trajectory` against the TUM file `groundTruth`, and the ATE plot when
/// `plotPath` is not empty. A run too short to evaluate records the reason instead of failing.
core::JsonValue evaluateTrajectory(const std::string& groundTruth,
                                   const core::Trajectory& trajectory, const std::string& plotPath,
                                   mrpt::system::COutputLogger& log)
{
    auto ev = core::JsonValue::object();
    ev.set("ground_truth", fs::absolute(groundTruth).string());
    const core::Trajectory gt = io::readTumTrajectory(groundTruth);  // a bad file is bad input
    try
    {
        const eval::AteOptions ao;
        const auto ate = eval::computeAte(gt, trajectory, ao);
        ev.set("ate", eval::ateToJson(ate, ao));
        eval::RpeOptions ro;
        ev.set("rpe_1s", eval::rpeToJson(eval::computeRpe(gt, trajectory, ro), ro));
        if (!plotPath.empty())
        {
            fs::create_directories(fs::path(plotPath).parent_path());
            eval::saveAtePlot(plotPath, ate);
        }
        log.logFmt(mrpt::system::LVL_INFO, "ATE RMSE %.4f m over %zu poses against '%s'",
                   ate.translation.rmse, ate.pairs, groundTruth.c_str());
    }
    catch (const std::exception& e)
    {
        // Too few matching poses (a very short or lost run): the run's outputs still count.
        ev.set("error", e.what());
        log.logStr(mrpt::system::LVL_WARN, std::string("no trajectory evaluation: ") + e.what());
    }
    return ev;
}

/// Stops a run whose first frames are all unreadable (the wrong folder, a camera that does not
/// fit the images): nothing after them is likely to be readable either.
void requireReadableStart(const RunLog& log, const std::string& input)
{
    constexpr size_t kUnreadableStart = 50;
    if (log.frames() == 0 && log.skipped() >= kUnreadableStart)
        throw core::InputError(mrpt::format(
            "the first %zu frames of '%s' could not be read (the first: '%s': %s); stopped",
            log.skipped(), input.c_str(), log.firstSkipped().file.c_str(),
            log.firstSkipped().reason.c_str()));
}

double peakMemoryMiB()
{
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;  // kB on Linux
}

void writeText(const fs::path& path, const std::string& text)
{
    core::AtomicTextFile f(path.string());
    f.stream() << text;
    f.commit();
}

}  // namespace

SemanticMapperApp::SemanticMapperApp() : COutputLogger("semantic-mapper") {}
SemanticMapperApp::~SemanticMapperApp() = default;

std::string SemanticMapperApp::defaultInput()
{
    return core::findDataFile("rawlogs/sample_walking_xyz.rawlog");
}

std::string SemanticMapperApp::configurationReference()
{
    io::FrameSourceParameters source;
    pipeline::SemanticMapperParameters params;
    mrpt::config::CConfigFileMemory cfg;
    source.saveToConfigFile(cfg, "");
    for (const auto* p : std::as_const(params).parts())
        p->saveToConfigFile(cfg, "");
    return cfg.getContent();
}

std::string SemanticMapperApp::usage()
{
    return "Usage: semantic-mapper [INPUT] [--config FILE]... [--out DIR] [--gt FILE]\n"
           "                       [--gt-labels DIR] [--gt-void ID|none] [--set "
           "section.key=value]...\n"
           "\n"
           "  INPUT        an MRPT .rawlog (plain or gzip) or a TUM RGB-D folder;\n"
           "               default: the embedded sample " +
           defaultInput() +
           "\n"
           "  --config F   INI configuration; several apply in order (camera preset, mode, ...;\n"
           "               see config/ and docs/configuration.md). Without a [camera], a TUM\n"
           "               folder's camera.ini or its name (freiburg1/2/3, 7scenes, rgbd_bonn) "
           "picks one\n"
           "  --out DIR    output folder (default: smap-out)\n"
           "  --gt F       ground-truth trajectory (TUM format) for ATE/RPE in metrics.json;\n"
           "               repeat it to report several (the first is the evaluation, the rest\n"
           "               other_references); default: the one the input ships (groundtruth.txt,\n"
           "               <rawlog>_groundtruth.txt) and any groundtruth_*.txt beside it\n"
           "  --gt-labels D  ground-truth labels/ and dynamic/ images per frame (smap-synth\n"
           "               layout) for Table III scores; default: <rawlog>_gt/, <folder>/gt/ or\n"
           "               the folder's own labels/ and dynamic/ when present\n"
           "  --gt-void ID|none  ground-truth label left out of the segmentation scores (255)\n"
           "  --set S.K=V  override one configuration key, e.g. --set input.max_frames=100\n"
           "  --dynamic-debug FRAMES  for these frames ('all' or e.g. '0,50-60') write\n"
           "               DIR/dynamic/NNNNNN.png and .csv (the dynamic filter's evidence)\n"
           "  --reproducible  byte-identical outputs run to run (= --set "
           "pipeline.reproducible=true):\n"
           "               no thread decides anything; metrics.json and frames.csv then hold no\n"
           "               timings (docs/pipeline.md, Reproducible runs)\n"
           "  --print-config  print every configuration key with its default and exit\n"
           "  --quiet      only warnings and errors\n"
           "  --help       this text\n"
           "\n"
           "Outputs in DIR (docs/pipeline.md, section Outputs): trajectory.txt (TUM, every\n"
           "  tracked frame), keyframes.txt, semantic_map.bin (MRPT CMultiMetricMap),\n"
           "  semantic_points.ply, semantic_octomap.ot/.bt, snapshots/*.png, annotated.rawlog\n"
           "  (one CObservationSemanticRGBD per keyframe), metrics.json, frames.csv,\n"
           "  config-effective.ini.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input (arguments, configuration, data),\n"
           "  130 interrupted (Ctrl-C; the outputs cover the frames processed).\n";
}

// ---- initialize ----

bool SemanticMapperApp::initialize(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("config")
        .option("out")
        .option("set")
        .option("gt")
        .option("gt-labels")
        .option("gt-void")
        .option("dynamic-debug")
        .flag("print-config")
        .flag("help")
        .flag("quiet")
        .flag("reproducible");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return false;
    }
    if (cl.has("print-config"))
    {
        out << configurationReference();
        return false;
    }
    if (cl.has("quiet"))
        setMinLoggingLevel(mrpt::system::LVL_WARN);
    if (cl.positionals().size() > 1)
        throw core::InputError("semantic-mapper takes at most one INPUT (see --help)");

    options.input = cl.positionals().empty() ? defaultInput() : cl.positionals()[0];
    if (options.input.empty())
        throw core::InputError(
            "no INPUT given and the embedded sample recording is missing from the data folder " +
            core::dataDirectory() + " (rawlogs/sample_walking_xyz.rawlog; see " +
            core::kDataDirectoryVariable + " in docs/pipeline.md)");
    options.outputDirectory = cl.value("out").value_or("smap-out");
    if (cl.has("dynamic-debug"))
        options.debugFrames = FrameSelection::parse(*cl.value("dynamic-debug"), "dynamic-debug");

    // Configuration: files, then --set overrides; every component loads its parameters once.
    std::vector<mrpt::config::CLoadableOptions*> parts = parameters.parts();
    parts.insert(parts.begin(), &sourceParameters);
    loadAppConfiguration(cl, parts, options.input, *this);
    if (cl.has("reproducible"))
        parameters.pipeline.reproducible = true;
    parameters.applyReproducibleMode();
    chooseSegmenter();
    parseGroundTruthOptions(cl);
    return true;
}

void SemanticMapperApp::chooseSegmenter()
{
    if (segmentation::useShippedModelIfUnset(parameters.segmentation))
        return;
    MRPT_LOG_WARN_STREAM("no segmentation model configured and the shipped model "
                         << segmentation::shippedModelPath()
                         << " does not exist (a broken installation?): keyframes are not "
                            "segmented ([segmentation] backend = none)");
    parameters.segmentation.backend = "none";
}

void SemanticMapperApp::parseGroundTruthOptions(const CommandLine& cl)
{
    options.groundTruths = cl.values("gt");
    for (const auto& gt : options.groundTruths)
        if (!fs::is_regular_file(gt))
            throw core::InputError("--gt '" + gt + "' is not a file");
    options.groundTruthLabels = cl.value("gt-labels").value_or("");
    if (!options.groundTruthLabels.empty() && !fs::is_directory(options.groundTruthLabels))
        throw core::InputError("--gt-labels '" + options.groundTruthLabels + "' is not a folder");
    if (const auto v = cl.value("gt-void"))
        options.groundTruthVoid = *v == "none" ? -1 : static_cast<int>(cl.integer("gt-void", 255));
    if (options.groundTruthVoid < -1 || options.groundTruthVoid > 255)
        throw core::InputError("--gt-void must be a label id in [0, 255] or 'none'");
}

// ---- run ----

/// One run's state, handed from step to step.
struct detail::MapperRun
{
    std::unique_ptr<io::FrameSource> source;
    fs::path dir;
    std::vector<std::string> references;  ///< ground-truth trajectories, the first evaluated
    std::string groundTruthLabels;
    std::unique_ptr<pipeline::SemanticMapper> mapper;
    std::unique_ptr<io::RawlogWriter> annotated;
    std::unique_ptr<KeyFrameScorer> scorer;
    RunLog log;
    bool interrupted = false;
    std::vector<std::string> files;  ///< outputs written, relative to dir
    core::Trajectory trajectory;
    mapping::SemanticMapBuilder::ReanchorResult reanchor;
    size_t mapPoints = 0, octoVoxels = 0, contributionBytes = 0, mapBytes = 0;
    std::vector<double> readMs;
    std::chrono::steady_clock::time_point start;
    double setupMs = 0.0, trackingWallS = 0.0, finishS = 0.0, outputS = 0.0, elapsedS = 0.0;
};

namespace
{
void trackOne(RunLog& log, pipeline::SemanticMapper& mapper, pipeline::FrameFeeder::Item& item,
              const std::string& input, ProgressReporter& progress,
              const std::function<void(const pipeline::SemanticMapper::PreparedFrame&)>& inspect)
{
    if (item.skipped)
    {
        log.addSkipped(*item.skipped);
        requireReadableStart(log, input);
        return;
    }
    const double stamp = item.frame.rgbd.timestamp;
    const core::PinholeCamera camera = item.frame.rgbd.camera;
    log.add(item.stats, stamp, camera, mapper.track(std::move(item.frame), inspect));
    progress.update(log.frames(), mrpt::format("%zu keyframes, %zu lost",
                                               mapper.keyframesSubmitted(), log.lost()));
}

core::JsonValue trackingSummary(const RunLog& log, const pipeline::SemanticMapper& mapper)
{
    const auto& slam = mapper.slam();
    const auto ms = slam.mappingStats();
    auto tracking = log.trackingJson();
    tracking.set("keyframes", static_cast<uint64_t>(slam.numKeyFrames()))
        .set("keyframes_culled", static_cast<uint64_t>(ms.keyframesCulled))
        .set("map_points", static_cast<uint64_t>(slam.numPoints()))
        .set("points_from_neighbours", static_cast<uint64_t>(ms.pointsFromNeighbours))
        .set("local_ba_runs", static_cast<uint64_t>(ms.baRuns))
        .set("local_ba_weakly_tied", static_cast<uint64_t>(ms.baWeaklyTiedHeld))
        .set("global_ba_keyframes",
             static_cast<uint64_t>(slam.globalBundleAdjustmentStats().keyframes))
        .set("global_ba_weakly_tied",
             static_cast<uint64_t>(slam.globalBundleAdjustmentStats().weaklyTiedHeld))
        .set("global_ba_outliers_removed",
             static_cast<uint64_t>(slam.globalBundleAdjustmentStats().outliersRemoved))
        .set("global_ba_seconds", slam.globalBundleAdjustmentSeconds());
    const auto parts = slam.mapPartStats();
    tracking.set("map_parts_started", static_cast<uint64_t>(parts.started))
        .set("map_parts_merged", static_cast<uint64_t>(parts.merged))
        .set("map_parts_discarded", static_cast<uint64_t>(parts.discarded));
    return tracking;
}

core::JsonValue loopClosureJson(const slam::LoopClosure& c)
{
    const Eigen::Quaterniond q(c.T_loop_keyframe.rotation());
    const Eigen::Vector3d t = c.T_loop_keyframe.translation();
    auto pose = core::JsonValue::array();
    for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()})
        pose.push(core::JsonValue::number(v));
    auto j = core::JsonValue::object();
    j.set("frame", c.frameId)
        .set("loop_frame", c.loopFrameId)
        .set("timestamp", c.timestamp)
        .set("loop_timestamp", c.loopTimestamp)
        .set("inliers", c.inliers)
        .set("projected_matches", c.projectedMatches)
        .set("T_loop_keyframe", std::move(pose))
        .set("corrected", c.corrected)
        .set("correction_m", c.correction_m)
        .set("correction_deg", c.correction_deg)
        .set("keyframes", c.keyframesCorrected)
        .set("points_fused", c.pointsFused)
        .set("correction_ms", 1e3 * c.correctionSeconds)
        .set("global_ba_ms", 1e3 * c.globalBaSeconds);
    return j;
}

/// Loop closing: keyframes checked, candidates, and every verified loop, corrected or a
/// consistent revisit (frames, the measured relative pose as tx ty tz qx qy qz qw, how far it
/// was from the keyframe's pose, its cost).
core::JsonValue loopSummary(const pipeline::SemanticMapper& mapper)
{
    const auto st = mapper.slam().loopClosingStats();
    std::vector<double> ms;
    auto list = core::JsonValue::array();
    uint64_t corrected = 0;
    for (const auto& c : st.closures)
    {
        if (c.corrected)
        {
            ms.push_back(1e3 * c.correctionSeconds);
            corrected++;
        }
        list.push(loopClosureJson(c));
    }
    std::sort(ms.begin(), ms.end());
    auto j = core::JsonValue::object();
    j.set("keyframes_checked", static_cast<uint64_t>(st.keyframesChecked))
        .set("candidates_verified", static_cast<uint64_t>(st.candidatesVerified))
        .set("candidates_rejected", static_cast<uint64_t>(st.candidatesRejected))
        .set("closures", corrected)
        .set("consistent_revisits", static_cast<uint64_t>(st.closures.size()) - corrected)
        .set("correction_median_ms", ms.empty() ? 0.0 : ms[ms.size() / 2])
        .set("correction_max_ms", ms.empty() ? 0.0 : ms.back())
        .set("list", std::move(list));
    return j;
}

core::JsonValue keyFrameSummary(pipeline::SemanticMapper& mapper,
                                const pipeline::PipelineParameters& params)
{
    const auto ws = mapper.worker().stats();
    const uint64_t pixels = ws.dynamicPixels + ws.staticPixels;
    auto kf = core::JsonValue::object();
    kf.set("submitted", static_cast<uint64_t>(mapper.keyframesSubmitted()))
        .set("mapped", static_cast<uint64_t>(ws.keyframes))
        .set("dropped_queue_full", static_cast<uint64_t>(ws.dropped))
        .set("tracking_waited_queue_full", static_cast<uint64_t>(ws.waits))
        .set("queue_capacity", params.keyframe_queue)
        .set("queue_high_water", static_cast<uint64_t>(ws.queueHighWater))
        .set("segmented_ahead", static_cast<uint64_t>(ws.segmentedAhead))
        .set("segmenter", mapper.worker().segmenterDescription())
        .set(
            "dynamic_pixel_fraction",
            pixels > 0 ? static_cast<double>(ws.dynamicPixels) / static_cast<double>(pixels) : 0.0);
    return kf;
}

core::JsonValue mapSummary(const detail::MapperRun& s)
{
    constexpr double kMiB = 1024.0 * 1024.0;
    auto mapj = core::JsonValue::object();
    mapj.set("points", static_cast<uint64_t>(s.mapPoints))
        .set("octomap_occupied_voxels", static_cast<uint64_t>(s.octoVoxels))
        .set("map_memory_mib", static_cast<double>(s.mapBytes) / kMiB)
        .set("contributions_mib", static_cast<double>(s.contributionBytes) / kMiB)
        .set("reanchored_keyframes", static_cast<uint64_t>(s.reanchor.moved))
        .set("discarded_keyframes", static_cast<uint64_t>(s.reanchor.discarded))
        .set("rebuilt", s.reanchor.rebuilt)
        .set("max_keyframe_correction_m", s.reanchor.maxTranslation)
        .set("max_keyframe_correction_deg", s.reanchor.maxRotationDeg)
        .set("pruned_free_points", static_cast<uint64_t>(s.reanchor.pruned))
        .set("unconfirmed_near_movers", static_cast<uint64_t>(s.reanchor.unconfirmed))
        .set("seen_through_near_movers", static_cast<uint64_t>(s.reanchor.seenThrough))
        .set("on_movable_bodies", static_cast<uint64_t>(s.reanchor.onBody));
    return mapj;
}

core::JsonValue timingSummary(const detail::MapperRun& s)
{
    const auto ws = s.mapper->worker().stats();
    const auto ms = s.mapper->slam().mappingStats();
    const double n = static_cast<double>(s.log.frames());
    auto timings = core::JsonValue::object();
    timings.set("setup_s", s.setupMs / 1000.0).set("read_decode", timingJson(s.readMs));
    s.log.addTimings(timings);
    timings.set("local_mapping_total_s", ms.totalSeconds)
        .set("local_ba_s", ms.baSeconds)
        .set("segmentation", timingJson(ws.segmentation_ms))
        .set("association", timingJson(ws.association_ms))
        .set("map_insertion", timingJson(ws.insertion_ms))
        .set("keyframe_outputs", timingJson(ws.observer_ms))
        .set("frames_done_s", s.trackingWallS)
        .set("finish_s", s.finishS)
        .set("outputs_s", s.outputS)
        .set("total_s", s.elapsedS)
        .set("frames_per_second", s.elapsedS > 0 ? n / s.elapsedS : 0.0)
        .set("peak_memory_mib", peakMemoryMiB());
    return timings;
}

/// Reproducible runs: metrics.json without the figures that measure the machine or depend on
/// the threads' timing (wall and CPU times, memory, queue levels, waits), all listed here.
void leaveOutMachineFigures(core::JsonValue& metrics)
{
    metrics.erase("timings");
    if (core::JsonValue* t = metrics.find("tracking"))
        t->erase("global_ba_seconds");
    if (core::JsonValue* k = metrics.find("keyframes"))
        for (const char* key :
             {"tracking_waited_queue_full", "queue_high_water", "segmented_ahead"})
            k->erase(key);
    core::JsonValue* loop = metrics.find("loop");
    if (!loop)
        return;
    loop->erase("correction_median_ms").erase("correction_max_ms");
    if (core::JsonValue* list = loop->find("list"))
        for (size_t i = 0; i < list->size(); ++i)
            list->at(i).erase("correction_ms").erase("global_ba_ms");
}

/// The first reference is the run's evaluation (and plot); each further one is reported beside
/// it (datasets whose pseudo ground truths disagree, e.g. 7-Scenes).
void addEvaluations(detail::MapperRun& s, bool plot, core::JsonValue& metrics,
                    mrpt::system::COutputLogger& logger)
{
    if (s.references.empty())
        return;
    const std::string plotPath = plot ? (s.dir / "snapshots" / "ate.png").string() : std::string();
    metrics.set("evaluation",
                evaluateTrajectory(s.references.front(), s.trajectory, plotPath, logger));
    if (!plotPath.empty() && fs::exists(plotPath))
        s.files.emplace_back("snapshots/ate.png");
    auto others = core::JsonValue::array();
    for (size_t k = 1; k < s.references.size(); k++)
        others.push(evaluateTrajectory(s.references[k], s.trajectory, {}, logger));
    if (s.references.size() > 1)
        metrics.set("other_references", others);
}
}  // namespace

int SemanticMapperApp::run(const std::vector<std::string>& args, std::ostream& out,
                           std::ostream* progress)
{
    if (!initialize(args, out))
        return kExitOk;
    return run(out, progress);
}

int SemanticMapperApp::run(std::ostream& out, std::ostream* progress)
{
    detail::MapperRun s;
    openInput(s);
    // Signals are blocked in this thread before any other starts, so every thread inherits it.
    const InterruptWatcher interrupt;
    startMapper(s);
    writeEffectiveConfiguration(s);
    attachKeyFrameOutputs(s);
    trackAllFrames(s, interrupt, progress);
    finishMapping(s);
    writeMapOutputs(s);
    writeMetrics(s);
    reportSummary(s, out);
    checkSkippedFraction(s);
    return s.interrupted ? kExitInterrupted : kExitOk;
}

void SemanticMapperApp::openInput(detail::MapperRun& s) const
{
    s.source = io::openFrameSource(options.input, sourceParameters);
    s.source->setMinLoggingLevel(getMinLoggingLevel());
    core::prepareOutputDirectory(options.outputDirectory, "--out");
    s.dir = fs::path(options.outputDirectory);
    s.references = options.groundTruths.empty()
                       ? io::referenceTrajectories(s.source->groundTruthPath())
                       : options.groundTruths;
    s.groundTruthLabels = options.groundTruthLabels.empty() ? KeyFrameScorer::findFor(options.input)
                                                            : options.groundTruthLabels;
}

void SemanticMapperApp::startMapper(detail::MapperRun& s) const
{
    s.start = std::chrono::steady_clock::now();
    s.mapper = std::make_unique<pipeline::SemanticMapper>(parameters);
    s.mapper->setLoggingLevel(getMinLoggingLevel());
    if (parameters.pipeline.opencv_threads > 0)
        cv::setNumThreads(parameters.pipeline.opencv_threads);
    s.setupMs = core::millisecondsSince(s.start);
    MRPT_LOG_INFO_STREAM("reading " << s.source->description() << " -> " << options.outputDirectory
                                    << "; keyframes segmented by "
                                    << s.mapper->worker().segmenterDescription());
}

void SemanticMapperApp::writeEffectiveConfiguration(detail::MapperRun& s) const
{
    mrpt::config::CConfigFileMemory effective;
    sourceParameters.saveToConfigFile(effective, "");
    for (const auto* p : parameters.parts())
        p->saveToConfigFile(effective, "");
    writeText(s.dir / "config-effective.ini",
              "# effective configuration of semantic-mapper (defaults, --config, --set)\n" +
                  effective.getContent());
    s.files = {"trajectory.txt", "keyframes.txt", "frames.csv", "config-effective.ini"};
}

/// The annotated rawlog and the segmentation scores, filled by the worker thread in keyframe
/// order.
void SemanticMapperApp::attachKeyFrameOutputs(detail::MapperRun& s) const
{
    if (parameters.pipeline.annotated_rawlog)
        s.annotated = std::make_unique<io::RawlogWriter>((s.dir / "annotated.rawlog").string(), 0);
    if (!s.groundTruthLabels.empty())
        s.scorer = std::make_unique<KeyFrameScorer>(
            s.groundTruthLabels, s.mapper->worker().labels(),
            parameters.segmentation.backend != "none", options.groundTruthVoid);
    s.mapper->setKeyFrameObserver(
        [annotated = s.annotated.get(), scorer = s.scorer.get()](
            const pipeline::KeyFrameJob& job, const maps::CObservationSemanticRGBD& obs,
            const mapping::DynamicRegions&)
        {
            if (annotated)
                annotated->write(obs);
            if (scorer)
                scorer->add(job.frame.name, obs);
        });
}

/// The frame loop: the front end (read and decode; features and dynamic filter) runs in two
/// threads and feeds tracking here.
void SemanticMapperApp::trackAllFrames(detail::MapperRun& s, const InterruptWatcher& interrupt,
                                       std::ostream* progressStream)
{
    const std::string outDir = options.outputDirectory;
    const FrameSelection debugFrames = options.debugFrames;
    pipeline::FrameFeeder feeder(*s.source, *s.mapper,
                                 static_cast<size_t>(parameters.pipeline.frame_queue),
                                 [&] { return interrupt.interrupted(); });
    ProgressReporter progress(s.source->sizeHint(), progressStream, *this);
    std::exception_ptr trackError;
    try
    {
        while (auto item = feeder.next())
        {
            // The dynamic-filter pictures show the verdicts tracking used (with the semantic
            // evidence).
            const size_t index = item->index;
            std::function<void(const pipeline::SemanticMapper::PreparedFrame&)> inspect;
            if (debugFrames.contains(index))
                inspect = [&outDir, index](const pipeline::SemanticMapper::PreparedFrame& p)
                { writeDynamicDebug(outDir, index, p); };
            trackOne(s.log, *s.mapper, *item, options.input, progress, inspect);
        }
    }
    catch (...)
    {
        trackError = std::current_exception();
    }
    feeder.close();
    progress.finish();
    if (trackError)
        std::rethrow_exception(trackError);
    s.readMs = feeder.readMilliseconds();
    s.interrupted = interrupt.interrupted();
    if (s.interrupted)
        MRPT_LOG_WARN_FMT(
            "interrupted after %zu frames: finishing the keyframes queued and "
            "writing the outputs (Ctrl-C again to abort)",
            s.log.frames());
    s.trackingWallS = core::secondsSince(s.start);
    if (s.log.frames() == 0 && s.log.skipped() > 0)
        throw core::InputError(
            mrpt::format("none of the %zu frames of '%s' could be read (the first: '%s': %s)",
                         s.log.skipped(), options.input.c_str(), s.log.firstSkipped().file.c_str(),
                         s.log.firstSkipped().reason.c_str()));
}

/// Drains the worker, re-anchors the maps at the final keyframe poses, writes the trajectories.
void SemanticMapperApp::finishMapping(detail::MapperRun& s)
{
    const auto tFinish = std::chrono::steady_clock::now();
    s.reanchor = s.mapper->finish();
    s.log.markDiscarded(s.mapper->slam().discardedFrames());
    s.finishS = core::secondsSince(tFinish);
    MRPT_LOG_DEBUG_STREAM("time per stage:\n" << s.mapper->profiler().getStatsAsText());
    if (s.annotated)
        s.annotated->commit();
    s.trajectory = s.mapper->trajectory();
    io::writeTumTrajectory((s.dir / "trajectory.txt").string(), s.trajectory,
                           "camera (optical frame) poses of every tracked frame, world = the "
                           "first keyframe's camera");
    io::writeTumTrajectory((s.dir / "keyframes.txt").string(), s.mapper->keyFrameTrajectory(),
                           "keyframe poses after bundle adjustment");
    writeText(s.dir / "frames.csv", s.log.framesCsv(!parameters.pipeline.reproducible));
    if (s.annotated)
        s.files.emplace_back("annotated.rawlog");
}

void SemanticMapperApp::writeMapOutputs(detail::MapperRun& s) const
{
    const auto tOut = std::chrono::steady_clock::now();
    maps::SnapshotOptions snap;
    snap.width = parameters.pipeline.snapshot_width;
    snap.height = parameters.pipeline.snapshot_height;
    snap.labels = s.mapper->worker().labels();
    const pipeline::MapOutputWriter writer(options.outputDirectory, snap);
    s.mapper->withMaps(
        [&](mapping::SemanticMapBuilder& b)
        {
            for (auto& f : writer.writeMaps(b))
                s.files.push_back(std::move(f));
            s.files.push_back(writer.writeScene(b, s.trajectory));
            if (parameters.pipeline.snapshots)
                for (auto& f : writer.writeSnapshots(b, s.trajectory))
                    s.files.push_back(std::move(f));
            s.mapPoints = b.pointsMap().size();
            s.octoVoxels = b.octoMap().occupiedVoxels().size();
            s.contributionBytes = b.contributionBytes();
            s.mapBytes = b.pointsMap().memoryBytes() + b.octoMap().memoryBytes();
        });
    s.outputS = core::secondsSince(tOut);
}

/// metrics.json: each part from its component's summary, then the evaluations.
void SemanticMapperApp::writeMetrics(detail::MapperRun& s)
{
    s.elapsedS = core::secondsSince(s.start);
    auto metrics = core::JsonValue::object();
    metrics.set("input", fs::absolute(options.input).string())
        .set("source", s.source->description());
    metrics.set("interrupted", s.interrupted);
    s.log.describeInput(metrics);
    metrics.set("input_ended_early", s.source->endedEarly());
    metrics.set("tracking", trackingSummary(s.log, *s.mapper));
    metrics.set("keyframes", keyFrameSummary(*s.mapper, parameters.pipeline));
    metrics.set("loop", loopSummary(*s.mapper));
    metrics.set("map", mapSummary(s));
    metrics.set("timings", timingSummary(s));
    metrics.set(
        "threads",
        mrpt::format("reading, front end %s, tracking, local mapping %s, keyframe worker",
                     parameters.pipeline.frame_queue > 0 ? "(own threads)" : "(on tracking)",
                     parameters.localMapping.threaded ? "(own thread)" : "(on tracking)"));
    addEvaluations(s, parameters.pipeline.snapshots, metrics, *this);
    if (s.scorer)
    {
        metrics.set("segmentation_scores", s.scorer->toJson());
        MRPT_LOG_INFO_STREAM(s.scorer->toText());
    }
    if (parameters.pipeline.reproducible)
        leaveOutMachineFigures(metrics);
    writeText(s.dir / "metrics.json", metrics.dump());
    s.files.emplace_back("metrics.json");
}

void SemanticMapperApp::reportSummary(const detail::MapperRun& s, std::ostream& out)
{
    if (const std::string diagnosis =
            s.log.trackingDiagnosis(parameters.tracking.min_depth, parameters.tracking.max_depth);
        !diagnosis.empty())
        MRPT_LOG_WARN(diagnosis);
    const size_t n = s.log.frames();
    const size_t mapped = s.mapper->worker().stats().keyframes;
    result_ = {n, mapped, s.interrupted, options.outputDirectory, options.input};
    const double elapsed = s.elapsedS;
    MRPT_LOG_INFO_FMT(
        "%zu frames in %.2f s (%.1f frames/s): %zu with a pose, %zu lost, %zu keyframes mapped, "
        "%zu map points",
        n, elapsed, elapsed > 0 ? static_cast<double>(n) / elapsed : 0.0, s.log.withPose(),
        s.log.lost(), mapped, s.mapPoints);
    out << "semantic-mapper: " << n << " frames from " << options.input << ", " << s.log.withPose()
        << " tracked, " << mapped << " keyframes mapped" << (s.interrupted ? " (interrupted)" : "")
        << "\noutputs in " << fs::absolute(options.outputDirectory).string() << "/:\n";
    for (const auto& f : s.files)
        out << "  " << f << "\n";
    if (s.log.discarded() > 0)
        MRPT_LOG_WARN_FMT(
            "%zu frames lost their pose with a part of the map that never met the "
            "rest again (status 'discarded' in frames.csv)",
            s.log.discarded());
    if (s.log.skipped() > 0)
        MRPT_LOG_WARN_FMT(
            "%zu of %zu frames skipped (unreadable; frames.csv and metrics.json "
            "list them), the first: '%s': %s",
            s.log.skipped(), n + s.log.skipped(), s.log.firstSkipped().file.c_str(),
            s.log.firstSkipped().reason.c_str());
}

void SemanticMapperApp::checkSkippedFraction(const detail::MapperRun& s) const
{
    const size_t framesRead = s.log.frames() + s.log.skipped();
    if (static_cast<double>(s.log.skipped()) >
        sourceParameters.max_skipped_fraction * static_cast<double>(framesRead))
    {
        throw core::InputError(mrpt::format(
            "%zu of the %zu frames of '%s' could not be read, more than [input] "
            "max_skipped_fraction = %g: the outputs cover the %zu readable frames, but the "
            "recording is damaged",
            s.log.skipped(), framesRead, options.input.c_str(),
            sourceParameters.max_skipped_fraction, s.log.frames()));
    }
}
}  // namespace smap::apps
