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
        {"walking_xyz", K::Xyz, 2, 0},
        {"walking_halfsphere", K::Halfsphere, 2, 0},
        {"walking_rpy", K::Rpy, 2, 0},
        {"walking_static", K::Static, 2, 0},
        {"sitting_xyz", K::Xyz, 0, 2},
        {"sitting_halfsphere", K::Halfsphere, 0, 2},
        {"desk_with_person", K::Handheld, 0, 1},
        {"static_xyz", K::Xyz, 0, 0},
        {"static_halfsphere", K::Halfsphere, 0, 0},
        {"static_rpy", K::Rpy, 0, 0},
        {"static_static", K::Static, 0, 0},
        {"static_handheld", K::Handheld, 0, 0},
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
    scene_ = std::make_unique<SyntheticScene>(
        SyntheticScene::makeOffice(options.seed, preset_.walking, preset_.sitting, sprites));
    motion_ = std::make_unique<CameraMotion>(preset_.motion, scene_->cameraBase(),
                                             scene_->cameraTarget(), options.seed);
    renderer_ = std::make_unique<SyntheticRenderer>(*scene_, options.camera);
}

SequenceGenerator::~SequenceGenerator() = default;

const SyntheticScene& SequenceGenerator::scene() const
{
    return *scene_;
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
