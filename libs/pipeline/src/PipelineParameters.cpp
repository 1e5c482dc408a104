#include "smap/pipeline/PipelineParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

namespace smap::pipeline
{
void PipelineParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                            const std::string&)
{
    const char* p = "pipeline";
    frame_queue = cfg.read_int(p, "frame_queue", frame_queue);
    keyframe_queue = cfg.read_int(p, "keyframe_queue", keyframe_queue);
    core::OptionFields(p, p)
        .addEnum("when_full", when_full, {{"wait", WhenFull::Wait}, {"drop", WhenFull::Drop}})
        .load(cfg);
    opencv_threads = cfg.read_int(p, "opencv_threads", opencv_threads);
    reproducible = cfg.read_bool(p, "reproducible", reproducible);
    if (frame_queue < 0 || frame_queue > 1000)
        throw core::InputError(
            mrpt::format("[pipeline] frame_queue = %d must be in [0, 1000]", frame_queue));
    if (keyframe_queue < 1 || keyframe_queue > 10000)
        throw core::InputError(
            mrpt::format("[pipeline] keyframe_queue = %d must be in [1, 10000]", keyframe_queue));
    if (opencv_threads < 0)
        throw core::InputError(
            mrpt::format("[pipeline] opencv_threads = %d must be >= 0", opencv_threads));

    const char* o = "output";
    annotated_rawlog = cfg.read_bool(o, "annotated_rawlog", annotated_rawlog);
    snapshots = cfg.read_bool(o, "snapshots", snapshots);
    snapshot_width = cfg.read_int(o, "snapshot_width", snapshot_width);
    snapshot_height = cfg.read_int(o, "snapshot_height", snapshot_height);
    if (snapshot_width < 64 || snapshot_height < 64 || snapshot_width > 8192 ||
        snapshot_height > 8192)
        throw core::InputError(mrpt::format(
            "[output] snapshot_width = %d and snapshot_height = %d must be in [64, 8192]",
            snapshot_width, snapshot_height));
}

void PipelineParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                          const std::string&) const
{
    const char* p = "pipeline";
    cfg.write(p, "frame_queue", frame_queue);
    cfg.write(p, "keyframe_queue", keyframe_queue);
    auto self = const_cast<PipelineParameters*>(this);  // saving only reads the field
    core::OptionFields(p, p)
        .addEnum("when_full", self->when_full, {{"wait", WhenFull::Wait}, {"drop", WhenFull::Drop}})
        .save(cfg);
    cfg.write(p, "opencv_threads", opencv_threads);
    cfg.write(p, "reproducible", reproducible);
    const char* o = "output";
    cfg.write(o, "annotated_rawlog", annotated_rawlog);
    cfg.write(o, "snapshots", snapshots);
    cfg.write(o, "snapshot_width", snapshot_width);
    cfg.write(o, "snapshot_height", snapshot_height);
}
}  // namespace smap::pipeline
