#include "smap/pipeline/SemanticMapper.h"

#include <map>

#include "smap/core/Elapsed.h"

namespace smap::pipeline
{
SemanticMapper::SemanticMapper(const SemanticMapperParameters& params)
    : COutputLogger("semantic-mapper"),
      params_(params),
      slam_(std::make_unique<slam::RgbdSlam>(params.orb, params.tracking, params.localMapping)),
      dynamicFilter_(params.dynamic),
      profiler_(true, "semantic-mapper")
{
    profiler_.setMinLoggingLevel(mrpt::system::LVL_ERROR);  // no statistics dump on exit
    auto segmenter = segmentation::makeSegmenter(params_.segmentation);
    worker_ = std::make_unique<KeyFrameWorker>(
        std::move(segmenter), segmentation::loadLabelSet(params_.segmentation), params_.association,
        params_.map, static_cast<size_t>(params_.pipeline.keyframe_queue));
}

SemanticMapper::~SemanticMapper() = default;

void SemanticMapper::setKeyFrameObserver(KeyFrameWorker::Observer observer)
{
    worker_->setObserver(std::move(observer));
}

SemanticMapper::PreparedFrame SemanticMapper::prepare(const core::RgbdFrame& frame)
{
    PreparedFrame p;
    p.rgbd = frame;
    const auto t0 = std::chrono::steady_clock::now();
    // Regions the previous frame found moving get features last (people filling most of the
    // view would otherwise take most of the budget from the background).
    p.features = slam_->prepare(frame, dynamicFilter_.moverRegions());
    p.extraction_ms = core::millisecondsSince(t0);
    p.dynamic =
        dynamicFilter_.process(frame.colour, frame.depth, p.features.features, frame.camera);
    profiler_.registerUserMeasure("frame.extraction", p.extraction_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.dynamic", p.dynamic.total_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.dynamic.ego_motion", p.dynamic.ego_motion_ms / 1000.0,
                                  true);
    profiler_.registerUserMeasure("frame.dynamic.warp", p.dynamic.warp_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.dynamic.flow", p.dynamic.flow_ms / 1000.0, true);
    p.features.setWeights(p.dynamic.weights());
    p.features.setMappable(p.dynamic.mappable());
    if (p.dynamic.egoMotion.valid && p.dynamic.framesBack > 0)
    {
        p.features.odometry_T_cam_earlier = p.dynamic.egoMotion.T_cur_prev;
        p.features.odometryFramesBack = p.dynamic.framesBack;
    }
    return p;
}

SemanticMapper::FrameResult SemanticMapper::track(PreparedFrame frame)
{
    FrameResult r;
    r.dynamicKeypoints = frame.dynamic.numDynamic();
    r.dynamic_ms = frame.dynamic.total_ms;

    // S of Algorithm 1, kept before the features move into the tracker.
    std::vector<mapping::DynamicPoint> dynamicPoints;
    const auto& fs = frame.features.features;
    for (size_t i = 0; i < frame.dynamic.keypoints.size() && i < fs.size(); ++i)
        if (frame.dynamic.keypoints[i].dynamic)
            dynamicPoints.push_back({fs.keypoints[i].pt.x, fs.keypoints[i].pt.y, fs.depth[i]});

    r.tracking = slam_->track(std::move(frame.features));
    r.tracking.timings.extraction_ms = frame.extraction_ms;
    profiler_.registerUserMeasure("frame.tracking", r.tracking.timings.total_ms / 1000.0, true);
    profiler_.registerUserMeasure("frame.tracking.optimisation",
                                  r.tracking.timings.optimisation_ms / 1000.0, true);
    if (r.tracking.newKeyFrame && slam::hasPose(r.tracking.status))
    {
        KeyFrameJob job;
        job.keyframe = r.tracking.keyFrameId.value_or(0);
        job.frameId = r.tracking.frameId;
        job.frame = std::move(frame.rgbd);
        job.T_world_cam = slam::toCPose3D(r.tracking.T_world_cam);
        job.dynamicPoints = std::move(dynamicPoints);
        const auto t0 = std::chrono::steady_clock::now();
        const bool queued =
            worker_->submit(std::move(job), params_.pipeline.when_full == WhenFull::Wait);
        r.queue_wait_ms = core::millisecondsSince(t0);
        profiler_.registerUserMeasure("frame.queue_wait", r.queue_wait_ms / 1000.0, true);
        r.keyframeDropped = !queued;
        keyframes_ += queued ? 1 : 0;
    }
    return r;
}

mapping::SemanticMapBuilder::ReanchorResult SemanticMapper::finish()
{
    slam_->finish();
    worker_->finish();
    const KeyFrameWorker::Stats ws = worker_->stats();
    for (const auto& [stage, times] : {std::pair{"keyframe.segmentation", &ws.segmentation_ms},
                                       std::pair{"keyframe.association", &ws.association_ms},
                                       std::pair{"keyframe.insertion", &ws.insertion_ms},
                                       std::pair{"keyframe.outputs", &ws.observer_ms}})
        for (const double ms : *times)
            profiler_.registerUserMeasure(stage, ms / 1000.0, true);
    // The final pose of every keyframe: its frame's pose through the refined keyframes (also
    // for a keyframe culled since).
    const std::map<uint64_t, mrpt::poses::CPose3D> finalPoses = slam_->framePoses();
    mapping::SemanticMapBuilder::ReanchorResult result;
    worker_->withMaps(
        [&](mapping::SemanticMapBuilder& b)
        {
            result = b.reanchor(
                [&](const mapping::KeyFrameContribution& c) -> std::optional<mrpt::poses::CPose3D>
                {
                    const auto it = finalPoses.find(c.frameId);
                    if (it == finalPoses.end())
                        return std::nullopt;
                    return it->second;
                });
            result.pruned = b.pruneFreePoints();
        });
    return result;
}
}  // namespace smap::pipeline
