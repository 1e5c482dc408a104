// [pipeline] and [output]: how semantic-mapper's stages are connected (queues, threads) and
// which output files it writes.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace smap::pipeline
{
/// What tracking does with a keyframe when the keyframe queue is full.
enum class WhenFull
{
    Wait,  ///< wait for room: every keyframe is mapped, results are deterministic
    Drop,  ///< never stall: the keyframe skips the map
};

struct PipelineParameters : public mrpt::config::CLoadableOptions
{
    /// Frames read and prepared (features, dynamic filter) ahead of tracking, in their own
    /// thread; 0 prepares them on the tracking thread.
    int frame_queue = 16;
    /// Keyframes waiting for segmentation and mapping (the worker thread).
    int keyframe_queue = 16;
    /// When the keyframe queue is full: "wait" (tracking pauses until the worker takes one:
    /// every keyframe reaches the map, results are deterministic) or "drop" (the keyframe skips
    /// the map; for live sensors that must never stall).
    WhenFull when_full = WhenFull::Wait;
    /// Threads of OpenCV's parallel framework (cv::setNumThreads), set once before the first
    /// frame: it overrides [onnx] threads; 0 = leave it as the segmenter set it.
    int opencv_threads = 2;
    /// Byte-identical outputs run to run: local mapping and loop closing on the tracking
    /// thread, semantic evidence from masks of a fixed latency, every keyframe mapped
    /// (SemanticMapperParameters::applyReproducibleMode), and no figures of the machine
    /// (timings, memory, queue levels) in metrics.json or frames.csv. false (the default):
    /// real time, and runs may differ by what the threads' timing decides.
    bool reproducible = false;

    // [output]
    /// Annotated rawlog: one CObservationSemanticRGBD per keyframe.
    bool annotated_rawlog = true;
    /// Map snapshots (by class, by colour, trajectory) and their size.
    bool snapshots = true;
    int snapshot_width = 1024;
    int snapshot_height = 768;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};
}  // namespace smap::pipeline
