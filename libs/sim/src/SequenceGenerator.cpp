#include "smap/sim/SequenceGenerator.h"

#include <mrpt/core/format.h>

#include "smap/core/DataDirectory.h"
#include "smap/core/InputError.h"
#include "smap/sim/PersonSprite.h"

namespace smap::sim
{
std::vector<SequencePreset> sequencePresets()
{
    using K = CameraMotionKind;
    return {
        {"walking_xyz", SceneKind::Office, K::Xyz, 2, 0},
        {"walking_halfsphere", SceneKind::Office, K::Halfsphere, 2, 0},
        {"walking_rpy", SceneKind::Office, K::Rpy, 2, 0},
        {"walking_static", SceneKind::Office, K::Static, 2, 0},
        {"sitting_xyz", SceneKind::Office, K::Xyz, 0, 2},
        {"sitting_halfsphere", SceneKind::Office, K::Halfsphere, 0, 2},
        {"desk_with_person", SceneKind::Office, K::Handheld, 0, 1},
        {"static_xyz", SceneKind::Office, K::Xyz, 0, 0},
        {"static_halfsphere", SceneKind::Office, K::Halfsphere, 0, 0},
        {"static_rpy", SceneKind::Office, K::Rpy, 0, 0},
        {"static_static", SceneKind::Office, K::Static, 0, 0},
        {"static_handheld", SceneKind::Office, K::Handheld, 0, 0},
        {"corridor_loop", SceneKind::CorridorLoop, K::Loop, 2, 0},
        {"static_corridor_loop", SceneKind::CorridorLoop, K::Loop, 0, 0},
    };
}

SequencePreset findPreset(const std::string& name)
{
    std::string names;
    for (const auto& p : sequencePresets())
    {
        if (p.name == name)
            return p;
        names += (names.empty() ? "" : ", ") + p.name;
    }
    throw core::InputError(
        mrpt::format("unknown preset '%s' (valid: %s)", name.c_str(), names.c_str()));
}

GeneratorOptions::GeneratorOptions() : peopleDirectory(core::findDataFile("people"))
{
    camera.width = 640;
    camera.height = 480;
    camera.fx = camera.fy = 525.0;
    camera.cx = 319.5;
    camera.cy = 239.5;
}

SequenceGenerator::SequenceGenerator(const GeneratorOptions& options)
    : options_(options), preset_(findPreset(options.preset))
{
    if (!(options.fps > 0.0))
        throw core::InputError(mrpt::format("fps = %g must be > 0", options.fps));
    std::vector<PersonSprite> sprites;
    if (preset_.walking + preset_.sitting > 0)
    {
        if (options.peopleDirectory.empty())
            throw core::InputError(mrpt::format(
                "preset '%s' has people, but the person cut-outs were not found (the data "
                "folder's people/, data/people in the source tree)",
                preset_.name.c_str()));
        sprites = loadPersonSprites(options.peopleDirectory);
    }
    if (preset_.scene == SceneKind::CorridorLoop)
    {
        scene_ = std::make_unique<SyntheticScene>(
            SyntheticScene::makeCorridorLoop(options.seed, preset_.walking, sprites));
        motion_ = std::make_unique<CameraMotion>(SyntheticScene::loopPath(), options.seed);
    }
    else
    {
        scene_ = std::make_unique<SyntheticScene>(
            SyntheticScene::makeOffice(options.seed, preset_.walking, preset_.sitting, sprites));
        motion_ = std::make_unique<CameraMotion>(preset_.motion, scene_->cameraBase(),
                                                 scene_->cameraTarget(), options.seed);
    }
    renderer_ = std::make_unique<SyntheticRenderer>(*scene_, options.camera);
}

SequenceGenerator::~SequenceGenerator() = default;

const SyntheticScene& SequenceGenerator::scene() const
{
    return *scene_;
}

core::RgbdFrame SequenceGenerator::rgbdFrame(size_t i)
{
    const SyntheticFrame f = frame(i);
    core::RgbdFrame r;
    r.colour = f.rendered.colour;
    r.depth = f.rendered.depth;
    r.camera = options_.camera;
    r.timestamp = f.timestamp;
    return r;
}

SyntheticFrame SequenceGenerator::frame(size_t i)
{
    SyntheticFrame f;
    f.index = i;
    const double t = static_cast<double>(i) / options_.fps;
    f.timestamp = options_.startTime + t;
    f.T_world_cam = motion_->T_world_cam(t);
    f.rendered = renderer_->render(t, f.T_world_cam, 1.0 / options_.fps);
    f.depthNoiseFree = f.rendered.depth;
    if (!options_.noiseFreeDepth)
    {
        // One generator per frame: frames can be made in any order with the same noise.
        std::mt19937 rng(options_.seed * 7919u + static_cast<uint32_t>(i) * 104729u);
        f.rendered.depth =
            options_.noise.apply(f.depthNoiseFree, f.rendered.colour, options_.camera, rng);
    }
    for (const auto& p : scene_->people())
        f.objectPoses.emplace_back("person" + std::to_string(p.instanceId()), p.rootPose(t));
    return f;
}
}  // namespace smap::sim
