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

int SemanticMapperApp::run(const std::vector<std::string>& args, std::ostream& out,
                           std::ostream* progressStream)
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
        .flag("quiet");
    cl.parse(args);
    if (cl.has("help"))
    {
        out << usage();
        return kExitOk;
    }
    if (cl.has("print-config"))
    {
        out << configurationReference();
        return kExitOk;
    }
    if (cl.has("quiet"))
        setMinLoggingLevel(mrpt::system::LVL_WARN);
    if (cl.positionals().size() > 1)
        throw core::InputError("semantic-mapper takes at most one INPUT (see --help)");

    const std::string input = cl.positionals().empty() ? defaultInput() : cl.positionals()[0];
    if (input.empty())
        throw core::InputError(
            "no INPUT given and the embedded sample recording is missing from the data folder " +
            core::dataDirectory() + " (rawlogs/sample_walking_xyz.rawlog; see " +
            core::kDataDirectoryVariable + " in docs/pipeline.md)");
    const std::string outDir = cl.value("out").value_or("smap-out");
    const FrameSelection debugFrames =
        cl.has("dynamic-debug") ? FrameSelection::parse(*cl.value("dynamic-debug"), "dynamic-debug")
                                : FrameSelection();

    // Configuration: files, then --set overrides; every component loads its parameters once.
    io::FrameSourceParameters sourceParams;
    pipeline::SemanticMapperParameters params;
    {
        std::vector<mrpt::config::CLoadableOptions*> parts = params.parts();
        parts.insert(parts.begin(), &sourceParams);
        loadAppConfiguration(cl, parts, input, *this);
    }
    auto& seg = params.segmentation;
    if (!useShippedModelIfUnset(seg))
    {
        MRPT_LOG_WARN_STREAM("no segmentation model configured and the shipped model "
                             << shippedModelPath()
                             << " does not exist (a broken installation?): keyframes are not "
                                "segmented ([segmentation] backend = none)");
        seg.backend = "none";
    }

    const std::vector<std::string> gtPaths = cl.values("gt");
    for (const auto& gt : gtPaths)
        if (!fs::is_regular_file(gt))
            throw core::InputError("--gt '" + gt + "' is not a file");
    std::string gtLabels = cl.value("gt-labels").value_or("");
    if (!gtLabels.empty() && !fs::is_directory(gtLabels))
        throw core::InputError("--gt-labels '" + gtLabels + "' is not a folder");
    int gtVoid = 255;
    if (const auto v = cl.value("gt-void"))
        gtVoid = *v == "none" ? -1 : static_cast<int>(cl.integer("gt-void", 255));
    if (gtVoid < -1 || gtVoid > 255)
        throw core::InputError("--gt-void must be a label id in [0, 255] or 'none'");

    auto source = io::openFrameSource(input, sourceParams);
    source->setMinLoggingLevel(getMinLoggingLevel());
    core::prepareOutputDirectory(outDir, "--out");
    const std::vector<std::string> references =
        gtPaths.empty() ? io::referenceTrajectories(source->groundTruthPath()) : gtPaths;
    if (gtLabels.empty())
        gtLabels = KeyFrameScorer::findFor(input);

    // Signals are blocked in this thread before any other starts, so every thread inherits it.
    InterruptWatcher interrupt;
    const auto tStart = std::chrono::steady_clock::now();
    pipeline::SemanticMapper mapper(params);
    mapper.setLoggingLevel(getMinLoggingLevel());
    if (params.pipeline.opencv_threads > 0)
        cv::setNumThreads(params.pipeline.opencv_threads);
    const double setupMs = core::millisecondsSince(tStart);

    const fs::path dir(outDir);
    MRPT_LOG_INFO_STREAM("reading " << source->description() << " -> " << outDir
                                    << "; keyframes segmented by "
                                    << mapper.worker().segmenterDescription());
    {
        mrpt::config::CConfigFileMemory effective;
        sourceParams.saveToConfigFile(effective, "");
        for (const auto* p : std::as_const(params).parts())
            p->saveToConfigFile(effective, "");
        writeText(dir / "config-effective.ini",
                  "# effective configuration of semantic-mapper (defaults, --config, --set)\n" +
                      effective.getContent());
    }

    // Keyframe outputs, written by the worker thread in keyframe order.
    std::unique_ptr<io::RawlogWriter> annotated;
    if (params.pipeline.annotated_rawlog)
        annotated = std::make_unique<io::RawlogWriter>((dir / "annotated.rawlog").string(), 0);
    std::unique_ptr<KeyFrameScorer> scorer;
    if (!gtLabels.empty())
        scorer = std::make_unique<KeyFrameScorer>(gtLabels, mapper.worker().labels(),
                                                  seg.backend != "none", gtVoid);
    mapper.setKeyFrameObserver(
        [&](const pipeline::KeyFrameJob& job, const maps::CObservationSemanticRGBD& obs,
            const mapping::DynamicRegions&)
        {
            if (annotated)
                annotated->write(obs);
            if (scorer)
                scorer->add(job.frame.name, obs);
        });

    // Front end (read and decode; features and dynamic filter) in two threads, feeding tracking.
    pipeline::FrameFeeder feeder(
        *source, mapper, static_cast<size_t>(params.pipeline.frame_queue),
        [&] { return interrupt.interrupted(); },
        [&](const pipeline::FrameFeeder::Item& item)
        {
            if (debugFrames.contains(item.index))
                writeDynamicDebug(outDir, item.index, item.frame);
        });

    RunLog log;
    ProgressReporter progress(source->sizeHint(), progressStream, *this);
    std::exception_ptr trackError;
    try
    {
        while (auto item = feeder.next())
        {
            if (item->skipped)
            {
                log.addSkipped(*item->skipped);
                requireReadableStart(log, input);
                continue;
            }
            const double stamp = item->frame.rgbd.timestamp;
            const core::PinholeCamera camera = item->frame.rgbd.camera;
            log.add(item->stats, stamp, camera, mapper.track(std::move(item->frame)));
            progress.update(log.frames(), mrpt::format("%zu keyframes, %zu lost",
                                                       mapper.keyframesSubmitted(), log.lost()));
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
    const bool interrupted = interrupt.interrupted();
    if (interrupted)
        MRPT_LOG_WARN_FMT(
            "interrupted after %zu frames: finishing the keyframes queued and "
            "writing the outputs (Ctrl-C again to abort)",
            log.frames());
    const double trackingWallS = core::secondsSince(tStart);
    if (log.frames() == 0 && log.skipped() > 0)
        throw core::InputError(mrpt::format(
            "none of the %zu frames of '%s' could be read (the first: '%s': %s)", log.skipped(),
            input.c_str(), log.firstSkipped().file.c_str(), log.firstSkipped().reason.c_str()));

    // Drain the worker, re-anchor, write.
    const auto tFinish = std::chrono::steady_clock::now();
    const auto reanchor = mapper.finish();
    const double finishS = core::secondsSince(tFinish);
    if (annotated)
        annotated->commit();
    const size_t n = log.frames();
    const core::Trajectory trajectory = mapper.trajectory();
    io::writeTumTrajectory((dir / "trajectory.txt").string(), trajectory,
                           "camera (optical frame) poses of every tracked frame, world = the "
                           "first keyframe's camera");
    io::writeTumTrajectory((dir / "keyframes.txt").string(), mapper.keyFrameTrajectory(),
                           "keyframe poses after bundle adjustment");
    writeText(dir / "frames.csv", log.framesCsv());

    const auto tOut = std::chrono::steady_clock::now();
    std::vector<std::string> files = {"trajectory.txt", "keyframes.txt", "frames.csv",
                                      "config-effective.ini"};
    if (annotated)
        files.emplace_back("annotated.rawlog");
    maps::SnapshotOptions snap;
    snap.width = params.pipeline.snapshot_width;
    snap.height = params.pipeline.snapshot_height;
    snap.labels = mapper.worker().labels();
    const pipeline::MapOutputWriter writer(outDir, snap);
    size_t mapPoints = 0, octoVoxels = 0, contributionBytes = 0, mapBytes = 0;
    mapper.withMaps(
        [&](mapping::SemanticMapBuilder& b)
        {
            for (auto& f : writer.writeMaps(b))
                files.push_back(std::move(f));
            if (params.pipeline.snapshots)
                for (auto& f : writer.writeSnapshots(b, trajectory))
                    files.push_back(std::move(f));
            mapPoints = b.pointsMap().size();
            octoVoxels = b.octoMap().occupiedVoxels().size();
            contributionBytes = b.contributionBytes();
            mapBytes = b.pointsMap().memoryBytes() + b.octoMap().memoryBytes();
        });
    const double outputS = core::secondsSince(tOut);

    // metrics.json
    const auto ws = mapper.worker().stats();
    const auto ms = mapper.slam().mappingStats();
    const double elapsed = core::secondsSince(tStart);

    auto metrics = core::JsonValue::object();
    metrics.set("input", fs::absolute(input).string()).set("source", source->description());
    metrics.set("interrupted", interrupted);
    log.describeInput(metrics);
    metrics.set("input_ended_early", source->endedEarly());
    auto tracking = log.trackingJson();
    tracking.set("keyframes", static_cast<uint64_t>(mapper.slam().numKeyFrames()))
        .set("keyframes_culled", static_cast<uint64_t>(ms.keyframesCulled))
        .set("map_points", static_cast<uint64_t>(mapper.slam().numPoints()))
        .set("local_ba_runs", static_cast<uint64_t>(ms.baRuns))
        .set("global_ba_keyframes",
             static_cast<uint64_t>(mapper.slam().globalBundleAdjustmentStats().keyframes))
        .set("global_ba_outliers_removed",
             static_cast<uint64_t>(mapper.slam().globalBundleAdjustmentStats().outliersRemoved))
        .set("global_ba_seconds", mapper.slam().globalBundleAdjustmentSeconds());
    metrics.set("tracking", tracking);
    auto kf = core::JsonValue::object();
    kf.set("submitted", static_cast<uint64_t>(mapper.keyframesSubmitted()))
        .set("mapped", static_cast<uint64_t>(ws.keyframes))
        .set("dropped_queue_full", static_cast<uint64_t>(ws.dropped))
        .set("tracking_waited_queue_full", static_cast<uint64_t>(ws.waits))
        .set("queue_capacity", params.pipeline.keyframe_queue)
        .set("queue_high_water", static_cast<uint64_t>(ws.queueHighWater))
        .set("segmenter", mapper.worker().segmenterDescription())
        .set("dynamic_pixel_fraction",
             ws.dynamicPixels + ws.staticPixels > 0
                 ? static_cast<double>(ws.dynamicPixels) /
                       static_cast<double>(ws.dynamicPixels + ws.staticPixels)
                 : 0.0);
    metrics.set("keyframes", kf);
    auto mapj = core::JsonValue::object();
    mapj.set("points", static_cast<uint64_t>(mapPoints))
        .set("octomap_occupied_voxels", static_cast<uint64_t>(octoVoxels))
        .set("map_memory_mib", static_cast<double>(mapBytes) / (1024.0 * 1024.0))
        .set("contributions_mib", static_cast<double>(contributionBytes) / (1024.0 * 1024.0))
        .set("reanchored_keyframes", static_cast<uint64_t>(reanchor.moved))
        .set("rebuilt", reanchor.rebuilt)
        .set("max_keyframe_correction_m", reanchor.maxTranslation)
        .set("max_keyframe_correction_deg", reanchor.maxRotationDeg)
        .set("pruned_free_points", static_cast<uint64_t>(reanchor.pruned));
    metrics.set("map", mapj);
    auto timings = core::JsonValue::object();
    timings.set("setup_s", setupMs / 1000.0)
        .set("read_decode", timingJson(feeder.readMilliseconds()));
    log.addTimings(timings);
    timings.set("local_mapping_total_s", ms.totalSeconds)
        .set("local_ba_s", ms.baSeconds)
        .set("segmentation", timingJson(ws.segmentationMs))
        .set("association", timingJson(ws.associationMs))
        .set("map_insertion", timingJson(ws.insertionMs))
        .set("keyframe_outputs", timingJson(ws.observerMs))
        .set("frames_done_s", trackingWallS)
        .set("finish_s", finishS)
        .set("outputs_s", outputS)
        .set("total_s", elapsed)
        .set("frames_per_second", elapsed > 0 ? static_cast<double>(n) / elapsed : 0.0)
        .set("peak_memory_mib", peakMemoryMiB());
    metrics.set("timings", timings);
    metrics.set("threads",
                mrpt::format("reading, front end %s, tracking, local mapping %s, keyframe worker",
                             params.pipeline.frame_queue > 0 ? "(own threads)" : "(on tracking)",
                             params.localMapping.threaded ? "(own thread)" : "(on tracking)"));
    if (!references.empty())
    {
        // The first reference is the run's evaluation (and plot); each further one is reported
        // beside it (datasets whose pseudo ground truths disagree, e.g. 7-Scenes).
        const std::string plot =
            params.pipeline.snapshots ? (dir / "snapshots" / "ate.png").string() : std::string();
        metrics.set("evaluation", evaluateTrajectory(references.front(), trajectory, plot, *this));
        if (!plot.empty() && fs::exists(plot))
            files.emplace_back("snapshots/ate.png");
        auto others = core::JsonValue::array();
        for (size_t k = 1; k < references.size(); k++)
            others.push(evaluateTrajectory(references[k], trajectory, {}, *this));
        if (references.size() > 1)
            metrics.set("other_references", others);
    }
    if (scorer)
    {
        metrics.set("segmentation_scores", scorer->toJson());
        MRPT_LOG_INFO_STREAM(scorer->toText());
    }
    writeText(dir / "metrics.json", metrics.dump());
    files.emplace_back("metrics.json");

    if (const std::string diagnosis =
            log.trackingDiagnosis(params.tracking.min_depth, params.tracking.max_depth);
        !diagnosis.empty())
        MRPT_LOG_WARN(diagnosis);
    result_ = {n, ws.keyframes, interrupted, outDir, input};
    const size_t framesRead = n + log.skipped();
    MRPT_LOG_INFO_FMT(
        "%zu frames in %.2f s (%.1f frames/s): %zu with a pose, %zu lost, %zu keyframes mapped, "
        "%zu map points",
        n, elapsed, elapsed > 0 ? static_cast<double>(n) / elapsed : 0.0, log.withPose(),
        log.lost(), ws.keyframes, mapPoints);
    out << "semantic-mapper: " << n << " frames from " << input << ", " << log.withPose()
        << " tracked, " << ws.keyframes << " keyframes mapped"
        << (interrupted ? " (interrupted)" : "") << "\noutputs in " << fs::absolute(outDir).string()
        << "/:\n";
    for (const auto& f : files)
        out << "  " << f << "\n";
    if (log.skipped() > 0)
    {
        MRPT_LOG_WARN_FMT(
            "%zu of %zu frames skipped (unreadable; frames.csv and metrics.json "
            "list them), the first: '%s': %s",
            log.skipped(), framesRead, log.firstSkipped().file.c_str(),
            log.firstSkipped().reason.c_str());
    }
    if (static_cast<double>(log.skipped()) >
        sourceParams.max_skipped_fraction * static_cast<double>(framesRead))
        throw core::InputError(mrpt::format(
            "%zu of the %zu frames of '%s' could not be read, more than [input] "
            "max_skipped_fraction = %g: the outputs cover the %zu readable frames, but the "
            "recording is damaged",
            log.skipped(), framesRead, input.c_str(), sourceParams.max_skipped_fraction, n));
    return interrupted ? kExitInterrupted : kExitOk;
}
}  // namespace smap::apps
