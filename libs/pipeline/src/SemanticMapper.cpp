#include "smap/pipeline/SemanticMapper.h"

#include <map>

#include "smap/core/Elapsed.h"

namespace smap::pipeline
{
SemanticMapper::SemanticMapper(const SemanticMapperParameters& params)
    : COutputLogger("semantic-mapper"),
      params_(params),
      slam_(std::make_unique<slam::RgbdSlam>(params.orb, params.tracking, params.localMapping)),
      dynamicFilter_(params.dynamic)
{
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
    p.extractionMs = core::millisecondsSince(t0);
    p.dynamic =
        dynamicFilter_.process(frame.colour, frame.depth, p.features.features, frame.camera);
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
    r.dynamicMs = frame.dynamic.milliseconds;

    // S of Algorithm 1, kept before the features move into the tracker.
    std::vector<mapping::DynamicPoint> dynamicPoints;
    const auto& fs = frame.features.features;
    for (size_t i = 0; i < frame.dynamic.keypoints.size() && i < fs.size(); ++i)
        if (frame.dynamic.keypoints[i].dynamic)
            dynamicPoints.push_back({fs.keypoints[i].pt.x, fs.keypoints[i].pt.y, fs.depth[i]});

    r.tracking = slam_->track(std::move(frame.features));
    r.tracking.timings.extraction_ms = frame.extractionMs;
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
        r.queueWaitMs = core::millisecondsSince(t0);
        r.keyframeDropped = !queued;
        keyframes_ += queued ? 1 : 0;
    }
    return r;
}

mapping::SemanticMapBuilder::ReanchorResult SemanticMapper::finish()
{
    slam_->finish();
    worker_->finish();
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
