#include "smap/pipeline/KeyFrameWorker.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "smap/core/Elapsed.h"

namespace smap::pipeline
{
KeyFrameWorker::KeyFrameWorker(std::unique_ptr<segmentation::Segmenter> segmenter,
                               core::LabelSet labels,
                               const mapping::DynamicRegionParameters& association,
                               const mapping::MapBuilderParameters& map, size_t queueCapacity)
    : COutputLogger("keyframe-worker"),
      segmenter_(std::move(segmenter)),
      labels_(std::move(labels)),
      finder_(association, labels_),
      builder_(map, labels_),
      queue_(queueCapacity)
{
    thread_ = std::thread([this] { run(); });
}

KeyFrameWorker::~KeyFrameWorker()
{
    queue_.close();
    if (thread_.joinable())
        thread_.join();
    if (board_)
        board_->close();
}

void KeyFrameWorker::setMaskBoard(MaskBoard* board, std::vector<bool> movable, int sampleStep,
                                  bool newestFirst)
{
    board_ = board;
    movable_ = std::move(movable);
    maskStep_ = sampleStep;
    newestFirst_ = newestFirst;
}

void KeyFrameWorker::publishMask(const KeyFrameJob& job, const cv::Mat& labels) const
{
    if (!board_)
        return;
    Eigen::Isometry3d T_world_cam;
    T_world_cam.matrix() =
        job.T_world_cam.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
    board_->publish(std::make_shared<const dynamic::MovableMask>(
        job.frameId, T_world_cam, labels, job.frame.depth, job.frame.camera, movable_, maskStep_));
}

void KeyFrameWorker::publishInOrder(const KeyFrameJob& job, const cv::Mat& labels)
{
    if (job.frameId + 1 <= newestPublished_)
        return;
    publishMask(job, labels);
    newestPublished_ = job.frameId + 1;
}

void KeyFrameWorker::segmentNewestAhead()
{
    if (!newestFirst_ || !board_)
        return;
    const std::optional<KeyFrameJob> newest = queue_.newest();
    if (!newest || newest->frameId + 1 <= newestPublished_)
        return;
    Labelled seg = segmentAtFrameSize(newest->frame);
    publishInOrder(*newest, seg.labels);
    segmentedAhead_[newest->frameId] = std::move(seg);
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_.segmentedAhead++;
}

KeyFrameWorker::Labelled KeyFrameWorker::segmentAtFrameSize(const core::RgbdFrame& f) const
{
    if (!segmenter_)
        return {cv::Mat(f.colour.size(), CV_8UC1, cv::Scalar(255)),
                cv::Mat(f.colour.size(), CV_32FC1, cv::Scalar(0.0F))};
    // Labels and their probability at the segmenter's working resolution, then brought to the
    // frame's (nearest / bilinear): resampling every class's probabilities instead
    // (Segmenter::segment) costs tens of ms per keyframe at 640x480 for the same labels away
    // from boundaries.
    const auto t0 = std::chrono::steady_clock::now();
    const segmentation::SegmentationResult seg = segmenter_->segmentNative(f);
    Labelled out{seg.labels, seg.labelConfidence(), 0.0};
    if (out.labels.size() != f.colour.size())
    {
        cv::resize(out.labels, out.labels, f.colour.size(), 0, 0, cv::INTER_NEAREST);
        cv::resize(out.confidence, out.confidence, f.colour.size(), 0, 0, cv::INTER_LINEAR);
    }
    out.ms = core::millisecondsSince(t0);
    return out;
}

std::string KeyFrameWorker::segmenterDescription() const
{
    return segmenter_ ? segmenter_->description() : "none";
}

bool KeyFrameWorker::submit(KeyFrameJob job, bool wait)
{
    {
        std::lock_guard<std::mutex> lock(statsMutex_);
        if (error_)
            std::rethrow_exception(error_);
    }
    bool queued = false;
    bool waited = false;
    if (wait)
        queued = queue_.push(std::move(job), &waited);
    else
        queued = queue_.tryPush(std::move(job));
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_.waits += waited ? 1 : 0;
    stats_.dropped += queued ? 0 : 1;
    return queued;
}

void KeyFrameWorker::finish()
{
    queue_.close();
    if (thread_.joinable())
        thread_.join();
    if (board_)
        board_->close();
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_.queueHighWater = queue_.highWater();
    if (error_)
        std::rethrow_exception(error_);
}

void KeyFrameWorker::withMaps(const std::function<void(mapping::SemanticMapBuilder&)>& fn)
{
    std::lock_guard<std::mutex> lock(mapMutex_);
    fn(builder_);
}

KeyFrameWorker::Stats KeyFrameWorker::stats() const
{
    std::lock_guard<std::mutex> lock(statsMutex_);
    Stats s = stats_;
    s.queueHighWater = queue_.highWater();
    return s;
}

void KeyFrameWorker::run()
{
    while (auto job = queue_.pop())
    {
        try
        {
            segmentNewestAhead();
            process(*job);
        }
        catch (...)
        {
            {
                std::lock_guard<std::mutex> lock(statsMutex_);
                error_ = std::current_exception();
            }
            // Nothing more is processed; tracking learns of it at its next submission.
            queue_.close();
            if (board_)
                board_->close();
            while (queue_.pop())
            {
            }
            return;
        }
    }
}

void KeyFrameWorker::process(KeyFrameJob& job)
{
    const core::RgbdFrame& f = job.frame;
    auto obs = maps::CObservationSemanticRGBD::Create();
    const auto ahead = segmentedAhead_.find(job.frameId);
    Labelled seg;
    if (ahead != segmentedAhead_.end())
    {
        seg = std::move(ahead->second);
        segmentedAhead_.erase(ahead);
    }
    else
    {
        seg = segmentAtFrameSize(f);
    }
    obs->labels = seg.labels;
    obs->confidence = seg.confidence;
    const double segMs = seg.ms;
    publishInOrder(job, obs->labels);

    auto t0 = std::chrono::steady_clock::now();
    const mapping::DynamicRegions regions = finder_.find(obs->labels, f.depth, job.dynamicPoints);
    const double assocMs = core::millisecondsSince(t0);

    obs->sensorLabel = "SEMANTIC_RGBD";
    obs->timestamp = mrpt::Clock::fromDouble(f.timestamp);
    // No robot pose in an annotated rawlog: the camera's world pose is the sensor pose, so
    // inserting the rawlog's observations into an empty map rebuilds the map.
    obs->sensorPose = job.T_world_cam;
    obs->camera = f.camera;
    obs->colour = f.colour;
    obs->depth = f.depth;
    obs->dynamicMask = regions.dynamicMask;

    t0 = std::chrono::steady_clock::now();
    {
        std::lock_guard<std::mutex> lock(mapMutex_);
        builder_.add(job.keyframe, job.frameId, f.timestamp,
                     {obs->colour, obs->depth, obs->labels, obs->confidence, obs->dynamicMask},
                     f.camera, job.T_world_cam);
    }
    const double insertMs = core::millisecondsSince(t0);

    t0 = std::chrono::steady_clock::now();
    if (observer_)
        observer_(job, *obs, regions);
    const double observer_ms = core::millisecondsSince(t0);

    const auto dynamicPixels = static_cast<size_t>(cv::countNonZero(regions.dynamicMask));
    std::lock_guard<std::mutex> lock(statsMutex_);
    stats_.keyframes++;
    stats_.segmentation_ms.push_back(segMs);
    stats_.association_ms.push_back(assocMs);
    stats_.insertion_ms.push_back(insertMs);
    stats_.observer_ms.push_back(observer_ms);
    stats_.dynamicPixels += dynamicPixels;
    stats_.staticPixels += regions.dynamicMask.total() - dynamicPixels;
    MRPT_LOG_DEBUG_FMT("keyframe %llu (%s): %.1f ms segmentation, %zu dynamic pixels",
                       static_cast<unsigned long long>(job.keyframe), f.name.c_str(), segMs,
                       dynamicPixels);
}
}  // namespace smap::pipeline
