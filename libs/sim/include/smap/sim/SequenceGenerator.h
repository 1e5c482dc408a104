// Synthetic RGB-D sequences with complete ground truth, by preset (the paper's TUM sequences
// and static_* twins with the same camera motion and no people).
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/core/RgbdFrame.h"
#include "smap/sim/CameraMotion.h"
#include "smap/sim/DepthNoiseModel.h"
#include "smap/sim/SyntheticRenderer.h"

namespace smap::sim
{
enum class SceneKind
{
    Office,       ///< SyntheticScene::makeOffice, the camera motions around its base
    CorridorLoop  ///< SyntheticScene::makeCorridorLoop, the camera around the loop
};

struct SequencePreset
{
    std::string name;
    SceneKind scene = SceneKind::Office;
    CameraMotionKind motion = CameraMotionKind::Static;
    int walking = 0;
    int sitting = 0;
};

/// walking_xyz, walking_halfsphere, walking_rpy, walking_static, sitting_xyz,
/// sitting_halfsphere, desk_with_person, and static_xyz, static_halfsphere, static_rpy,
/// static_static, static_handheld (no people); corridor_loop (a 43 m lap of a ring corridor,
/// two people walking in it) and its twin static_corridor_loop.
std::vector<SequencePreset> sequencePresets();
/// Throws core::InputError listing the valid names.
SequencePreset findPreset(const std::string& name);

struct GeneratorOptions
{
    std::string preset = "walking_xyz";
    uint32_t seed = 1;
    double fps = 30.0;
    double startTime = 1.0e9;  ///< timestamp of frame 0, seconds
    bool noiseFreeDepth = false;
    DepthNoiseModel noise;
    core::PinholeCamera camera;  ///< default: 640x480, f = 525, c = (319.5, 239.5)
    /// Person cut-outs (loadPersonSprites) for presets with people; default: people/ in the
    /// data folder (core::findDataFile), empty when it is not there.
    std::string peopleDirectory;

    GeneratorOptions();
};

struct SyntheticFrame
{
    size_t index = 0;
    double timestamp = 0.0;
    mrpt::poses::CPose3D T_world_cam;
    RenderedFrame rendered;  ///< depth here is the sensor depth (noisy unless noise-free)
    cv::Mat depthNoiseFree;
    /// Root pose (on the floor, x forward) of every person, by name "person<instance>".
    std::vector<std::pair<std::string, mrpt::poses::CPose3D>> objectPoses;
};

class SequenceGenerator
{
public:
    explicit SequenceGenerator(const GeneratorOptions& options);
    ~SequenceGenerator();

    /// Frame i (any order; deterministic for the options' seed).
    SyntheticFrame frame(size_t i);
    /// Frame i as the pipeline takes it: colour, sensor depth, timestamp, the options' camera.
    core::RgbdFrame rgbdFrame(size_t i);
    const SyntheticScene& scene() const;
    const SequencePreset& preset() const { return preset_; }
    const GeneratorOptions& options() const { return options_; }

private:
    GeneratorOptions options_;
    SequencePreset preset_;
    std::unique_ptr<SyntheticScene> scene_;
    std::unique_ptr<CameraMotion> motion_;
    std::unique_ptr<SyntheticRenderer> renderer_;
};
}  // namespace smap::sim
