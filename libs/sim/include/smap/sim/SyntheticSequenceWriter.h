// Writes generated frames to disk in the TUM RGB-D layout plus ground-truth folders.
//
// DIR/rgb/NNNNNN.png (or .jpg), depth/NNNNNN.png (16-bit, factor 5000), labels/ (8-bit VOC ids),
// instances/ (16-bit), dynamic/ (8-bit, 255 = moving), rgb.txt, depth.txt, associations.txt,
// groundtruth.txt (T_world_cam), objects/<name>.txt (world trajectory of each person's root,
// TUM format), meta.json (preset, seed, intrinsics, depth factor, instances and classes).
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <functional>
#include <map>
#include <string>

#include "smap/core/JsonWriter.h"
#include "smap/core/Trajectory.h"
#include "smap/sim/SequenceGenerator.h"

namespace smap::sim
{
class SyntheticSequenceWriter : public mrpt::system::COutputLogger
{
public:
    SyntheticSequenceWriter();
    /// Renders frames [0, frames) and writes them into `folder`, which appears only when
    /// complete (written under a temporary name, then renamed); an existing folder is replaced only
    /// when empty or an earlier smap-synth output (isSmapSynthOutput), else InputError.
    void write(sim::SequenceGenerator& generator, size_t frames, const std::string& folder);

    /// Frame i of any source (rendered or composited), its meta.json content and the camera the
    /// frames are in (written as the folder's camera.ini, with the depth factor, so that the apps
    /// read the folder without a --config; see InputPreset).
    using FrameProducer = std::function<sim::SyntheticFrame(size_t)>;
    void write(const FrameProducer& produce, size_t frames, const core::JsonValue& meta,
               const core::PinholeCamera& camera, const std::string& folder);
    static core::JsonValue metaFor(const sim::SequenceGenerator& generator, size_t frames);

    /// Colour as JPEG of this quality (1 - 100) instead of PNG; 0 = PNG (default).
    void setColourJpegQuality(int quality) { jpegQuality_ = quality; }

    static constexpr double kDepthFactor = 5000.0;

private:
    /// The frames' images, lists and ground truth into `folder`; each object's trajectory into
    /// `objects`.
    void writeFrames(const FrameProducer& produce, size_t frames, const std::string& folder,
                     std::map<std::string, core::Trajectory>& objects);

    int jpegQuality_ = 0;
};

/// A PNG contact sheet of `count` frames spread over the sequence folder: colour, labels
/// overlay, dynamic-mask overlay and depth, one row per frame.
void writeContactSheet(const std::string& sequenceFolder, size_t count, const std::string& pngPath);
}  // namespace smap::sim
