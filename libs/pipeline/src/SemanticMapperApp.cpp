#include "smap/pipeline/SemanticMapperApp.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/system/CTicTac.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/JsonWriter.h"
#include "smap/dynamic/DynamicFilter.h"
#include "smap/dynamic/EvidenceReport.h"
#include "smap/features/OrbParameters.h"
#include "smap/io/FrameSource.h"
#include "smap/io/TumTextFormats.h"
#include "smap/pipeline/AppConfiguration.h"
#include "smap/pipeline/CommandLine.h"
#include "smap/pipeline/FrameSelection.h"
#include "smap/pipeline/FrameSummary.h"
#include "smap/slam/RgbdSlam.h"

namespace fs = std::filesystem;

namespace smap::pipeline
{
namespace
{
/// DIR/dynamic/NNNNNN.png (the paper's Figure 4 style) and .csv (evidence per keypoint).
void writeDynamicDebug(const std::string& outDir, size_t index, const core::RgbdFrame& frame,
                       const features::FeatureSet& features, const dynamic::DynamicResult& dyn)
{
    const fs::path dir = fs::path(outDir) / "dynamic";
    fs::create_directories(dir);
    const std::string stem = (dir / mrpt::format("%06zu", index)).string();
    const cv::Mat picture = dynamic::drawEvidence(frame.colour, features, dyn);
    core::writeFileAtomically(stem + ".png",
                              [&](const std::string& tmp)
                              {
                                  if (!cv::imwrite(tmp, picture))
                                      throw std::runtime_error("cannot write " + stem + ".png");
                              });
    core::AtomicTextFile csv(stem + ".csv");
    csv.stream() << dynamic::evidenceCsv(features, dyn);
    csv.commit();
}
}  // namespace

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
           "  --dynamic-debug FRAMES  for these frames ('all' or e.g. '0,50-60') write\n"
           "               DIR/dynamic/NNNNNN.png (static keypoints red dots, dynamic green +)\n"
           "               and DIR/dynamic/NNNNNN.csv (per-keypoint evidence)\n"
           "  --quiet      only warnings and errors\n"
           "  --help       this text\n"
           "\n"
           "Outputs in DIR: trajectory.txt (TUM, every tracked frame), keyframes.txt,\n"
           "               frames.csv (per-frame status and timings), summary.json,\n"
           "               config-effective.ini.\n"
           "Exit codes: 0 ok, 1 internal error, 2 bad input (arguments, configuration, data).\n";
}

int SemanticMapperApp::run(const std::vector<std::string>& args, std::ostream& out)
{
    CommandLine cl;
    cl.option("config")
        .option("out")
        .option("set")
        .option("dynamic-debug")
        .flag("help")
        .flag("quiet");
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
    const FrameSelection debugFrames =
        cl.has("dynamic-debug") ? FrameSelection::parse(*cl.value("dynamic-debug"), "dynamic-debug")
                                : FrameSelection();

    // Configuration: file, then --set overrides; every component loads its parameters once.
    io::FrameSourceParameters sourceParams;
    features::OrbParameters orbParams;
    slam::TrackerParameters trackingParams;
    slam::LocalMappingParameters mappingParams;
    dynamic::DynamicParameters dynamicParams;
    loadAppConfiguration(
        cl, {&sourceParams, &orbParams, &trackingParams, &mappingParams, &dynamicParams});

    auto source = io::openFrameSource(input, sourceParams);
    source->setMinLoggingLevel(getMinLoggingLevel());
    fs::create_directories(outDir);
    MRPT_LOG_INFO_STREAM("reading " << source->description() << " -> " << outDir);

    {
        mrpt::config::CConfigFileMemory effective;
        for (const mrpt::config::CLoadableOptions* p :
             std::vector<const mrpt::config::CLoadableOptions*>{
                 &sourceParams, &orbParams, &trackingParams, &mappingParams, &dynamicParams})
            p->saveToConfigFile(effective, "");
        core::AtomicTextFile f((fs::path(outDir) / "config-effective.ini").string());
        f.stream() << "# effective configuration of semantic-mapper (defaults, --config, --set)\n"
                   << effective.getContent();
        f.commit();
    }

    core::AtomicTextFile csv((fs::path(outDir) / "frames.csv").string());
    csv.stream()
        << frameStatsCsvHeader()
        << ",status,keypoints,inliers,keyframe,extraction_ms,matching_ms,"
           "optimisation_ms,tracking_ms,dynamic_keypoints,dynamic_filter_ms,dynamic_ego_ms,"
           "dynamic_warp_ms,dynamic_flow_ms\n";
    dynamic::DynamicFilter dynamicFilter(dynamicParams);
    slam::RgbdSlam slam(orbParams, trackingParams, mappingParams);
    slam.setLoggingLevel(getMinLoggingLevel());
    std::vector<double> trackingMs, extractionMs;
    size_t tracked = 0, lost = 0, relocalised = 0, reanchored = 0;
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
        const auto tExtract = std::chrono::steady_clock::now();
        slam::Frame prepared = slam.prepare(*frame);
        const double frameExtractionMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tExtract)
                .count();
        const dynamic::DynamicResult dyn =
            dynamicFilter.process(frame->colour, frame->depth, prepared.features, frame->camera);
        if (debugFrames.contains(n))
            writeDynamicDebug(outDir, n, *frame, prepared.features, dyn);
        prepared.setWeights(dyn.weights());
        if (dyn.egoMotion.valid && dyn.framesBack > 0)
        {
            prepared.odometry_T_cam_earlier = dyn.egoMotion.T_cur_prev;
            prepared.odometryFramesBack = dyn.framesBack;
        }
        slam::TrackingResult tr = slam.track(std::move(prepared));
        tr.timings.extraction_ms = frameExtractionMs;
        tracked += slam::hasPose(tr.status) ? 1 : 0;
        lost += tr.status == slam::TrackingStatus::Lost ? 1 : 0;
        relocalised += tr.status == slam::TrackingStatus::Relocalised ? 1 : 0;
        reanchored += tr.status == slam::TrackingStatus::Reanchored ? 1 : 0;
        trackingMs.push_back(tr.timings.total_ms);
        extractionMs.push_back(tr.timings.extraction_ms);
        csv.stream() << toCsvRow(s) << "," << slam::toString(tr.status) << "," << tr.keypoints
                     << "," << tr.inliers << "," << (tr.newKeyFrame ? 1 : 0) << ","
                     << mrpt::format("%.3f,%.3f,%.3f,%.3f", tr.timings.extraction_ms,
                                     tr.timings.matching_ms, tr.timings.optimisation_ms,
                                     tr.timings.total_ms)
                     << "," << dyn.numDynamic() << ","
                     << mrpt::format("%.3f,%.3f,%.3f,%.3f", dyn.milliseconds,
                                     dyn.egoMotionMilliseconds, dyn.warpMilliseconds,
                                     dyn.flowMilliseconds)
                     << "\n";
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
                MRPT_LOG_INFO_FMT("frame %zu / %zu  %.1f frames/s  ETA %.0f s  (%zu lost)", n,
                                  *total, fps, (*total - n) / fps, lost);
            else
                MRPT_LOG_INFO_FMT("frame %zu  %.1f frames/s  (%zu lost)", n, fps, lost);
        }
    }
    slam.finish();
    csv.commit();
    const double elapsed = timer.Tac();
    const core::Trajectory trajectory = slam.trajectory();
    io::writeTumTrajectory((fs::path(outDir) / "trajectory.txt").string(), trajectory,
                           "camera (optical frame) poses of every tracked frame, world = first "
                           "tracked camera");
    io::writeTumTrajectory((fs::path(outDir) / "keyframes.txt").string(), slam.keyFrameTrajectory(),
                           "keyframe poses after local BA");
    auto median = [](std::vector<double> v)
    {
        if (v.empty())
            return 0.0;
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    const auto mapStats = slam.mappingStats();

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
    auto tracking = core::JsonValue::object();
    tracking.set("frames_with_pose", static_cast<uint64_t>(tracked))
        .set("frames_lost", static_cast<uint64_t>(lost))
        .set("relocalisations", static_cast<uint64_t>(relocalised))
        .set("reanchors", static_cast<uint64_t>(reanchored))
        .set("keyframes", static_cast<uint64_t>(slam.numKeyFrames()))
        .set("keyframes_culled", static_cast<uint64_t>(mapStats.keyframesCulled))
        .set("map_points", static_cast<uint64_t>(slam.numPoints()))
        .set("median_extraction_ms", median(extractionMs))
        .set("median_tracking_ms", median(trackingMs))
        .set("local_ba_runs", static_cast<uint64_t>(mapStats.baRuns))
        .set("local_mapping_s", mapStats.totalSeconds);
    summary.set("tracking", tracking);
    summary.set("processing_time_s", elapsed)
        .set("frames_per_second", elapsed > 0 ? n / elapsed : 0.0);
    {
        core::AtomicTextFile f((fs::path(outDir) / "summary.json").string());
        f.stream() << summary.dump();
        f.commit();
    }

    result_ = {n, outDir, input};
    MRPT_LOG_INFO_FMT(
        "%zu frames in %.2f s (%.1f frames/s): %zu with a pose, %zu lost, %zu "
        "keyframes, %zu map points",
        n, elapsed, elapsed > 0 ? n / elapsed : 0.0, tracked, lost, slam.numKeyFrames(),
        slam.numPoints());
    out << "semantic-mapper: " << n << " frames from " << input << ", " << tracked << " tracked\n"
        << "outputs in " << fs::absolute(outDir).string()
        << "/: trajectory.txt, keyframes.txt, summary.json, frames.csv, config-effective.ini\n";
    return kExitOk;
}
}  // namespace smap::pipeline
