#include "smap/sim/SyntheticScene.h"

#include <mrpt/core/format.h>

#include <random>
#include <stdexcept>

#include "smap/core/InputError.h"
#include "smap/sim/ProceduralTexture.h"

namespace smap::sim
{
namespace
{
/// Metres a person's silhouette bulges towards the camera at its widest rows.
constexpr double kPersonRelief = 0.12;
}  // namespace

int SyntheticScene::addTexture(const cv::Mat& t)
{
    textures_.push_back(t);
    return static_cast<int>(textures_.size()) - 1;
}

SceneObject& SyntheticScene::addObject(const std::string& name, uint8_t classId, int texture)
{
    SceneObject o;
    o.name = name;
    o.classId = classId;
    o.instanceId = nextInstance_++;
    o.textureIndex = texture;
    instanceClasses_[o.instanceId] = classId;
    objects_.push_back(std::move(o));
    return objects_.back();
}

SyntheticScene SyntheticScene::makeOffice(uint32_t seed, int walking, int sitting,
                                          const std::vector<PersonSprite>& sprites)
{
    if (walking < 0 || walking > 3 || sitting < 0 || sitting > 2)
        throw std::invalid_argument(
            mrpt::format("makeOffice: %d walking (0-3), %d sitting (0-2)", walking, sitting));
    SyntheticScene s;
    s.addRoomAndFurniture(seed);
    s.addPeople(seed, walking, sitting, sprites);
    return s;
}

void SyntheticScene::addRoomAndFurniture(uint32_t seed)
{
    SyntheticScene& s = *this;
    const int ts = 512;
    uint32_t k = seed * 1000u;
    const int wallTex = s.addTexture(makeTexture(TextureKind::Noise, ts, k++));
    const int wall2Tex = s.addTexture(makeTexture(TextureKind::Tiles, ts, k++));
    const int floorTex = s.addTexture(makeTexture(TextureKind::Carpet, ts, k++));
    const int ceilingTex = s.addTexture(makeTexture(TextureKind::Noise, ts, k++));
    const int woodTex = s.addTexture(makeTexture(TextureKind::Wood, ts, k++));
    const int posterTex = s.addTexture(makeTexture(TextureKind::Poster, ts, k++));
    const int fabricTex = s.addTexture(makeTexture(TextureKind::Fabric, ts, k++));
    const int screenTex = s.addTexture(makeTexture(TextureKind::Poster, ts, k++));
    const int plantTex = s.addTexture(makeTexture(TextureKind::Carpet, ts, k++));
    const float cell = 0.9f;
    const float W = 6.0f, D = 5.0f, H = 2.8f;

    auto& floor = s.addObject("floor", voc::kBackground, floorTex);
    addRectangle(floor, {0, 0, 0}, {W, 0, 0}, {0, D, 0}, cell, k++);
    auto& ceiling = s.addObject("ceiling", voc::kBackground, ceilingTex);
    addRectangle(ceiling, {0, 0, H}, {W, 0, 0}, {0, D, 0}, cell, k++);
    auto& north = s.addObject("wall_north", voc::kBackground, wallTex);
    addRectangle(north, {0, D, 0}, {W, 0, 0}, {0, 0, H}, cell, k++);
    auto& south = s.addObject("wall_south", voc::kBackground, wall2Tex);
    addRectangle(south, {0, 0, 0}, {W, 0, 0}, {0, 0, H}, cell, k++);
    auto& west = s.addObject("wall_west", voc::kBackground, wall2Tex);
    addRectangle(west, {0, 0, 0}, {0, D, 0}, {0, 0, H}, cell, k++);
    auto& east = s.addObject("wall_east", voc::kBackground, wallTex);
    addRectangle(east, {W, 0, 0}, {0, D, 0}, {0, 0, H}, cell, k++);

    // Door and window: thin boxes standing 2 cm off the walls.
    auto& door = s.addObject("door", voc::kBackground, woodTex);
    addBox(door, {4.6f, D - 0.02f, 1.0f}, {0.9f, 0.04f, 2.0f}, cell, k++);
    auto& window = s.addObject("window", voc::kBackground, posterTex);
    addBox(window, {0.02f, 1.5f, 1.5f}, {0.04f, 1.4f, 1.0f}, cell, k++);
    auto& poster = s.addObject("poster", voc::kBackground, posterTex);
    addBox(poster, {1.6f, D - 0.02f, 1.6f}, {1.0f, 0.04f, 0.7f}, cell, k++);

    // Desk (diningtable) with a monitor, in front of the north wall.
    auto& desk = s.addObject("desk", voc::kDiningTable, woodTex);
    addBox(desk, {3.0f, 3.2f, 0.73f}, {1.6f, 0.8f, 0.04f}, cell, k++);
    for (float dx : {-0.75f, 0.75f})
        for (float dy : {-0.35f, 0.35f})
            addBox(desk, {3.0f + dx, 3.2f + dy, 0.355f}, {0.05f, 0.05f, 0.71f}, cell, k++);
    auto& monitor = s.addObject("monitor", voc::kTvMonitor, screenTex);
    addBox(monitor, {3.45f, 3.35f, 1.02f}, {0.55f, 0.04f, 0.36f}, cell, k++);
    addBox(monitor, {3.45f, 3.4f, 0.8f}, {0.06f, 0.06f, 0.12f}, cell, k++);

    auto addChair = [&](const std::string& name, float x, float y, float backDy)
    {
        auto& c = s.addObject(name, voc::kChair, woodTex);
        addBox(c, {x, y, 0.45f}, {0.45f, 0.45f, 0.05f}, cell, k++);
        addBox(c, {x, y + backDy, 0.72f}, {0.45f, 0.04f, 0.5f}, cell, k++);
        for (float dx : {-0.2f, 0.2f})
            for (float dy : {-0.2f, 0.2f})
                addBox(c, {x + dx, y + dy, 0.215f}, {0.04f, 0.04f, 0.43f}, cell, k++);
    };
    addChair("chair_desk", 2.85f, 3.95f, 0.22f);
    addChair("chair_side", 4.65f, 3.3f, 0.22f);

    auto& sofa = s.addObject("sofa", voc::kSofa, fabricTex);
    addBox(sofa, {0.5f, 2.6f, 0.22f}, {0.8f, 1.8f, 0.44f}, cell, k++);
    addBox(sofa, {0.15f, 2.6f, 0.6f}, {0.2f, 1.8f, 0.5f}, cell, k++);

    auto& plant = s.addObject("potted_plant", voc::kPottedPlant, plantTex);
    addBox(plant, {5.5f, 4.5f, 0.2f}, {0.35f, 0.35f, 0.4f}, cell, k++);
    addBox(plant, {5.5f, 4.5f, 0.75f}, {0.6f, 0.6f, 0.7f}, cell, k++);

    auto& shelves = s.addObject("shelves", voc::kBackground, woodTex);
    addBox(shelves, {5.8f, 2.2f, 1.0f}, {0.35f, 1.2f, 2.0f}, cell, k++);
    auto& books = s.addObject("books", voc::kBackground, posterTex);
    for (int shelf = 0; shelf < 4; shelf++)
        addBox(books, {5.6f, 2.2f, 0.3f + 0.45f * shelf}, {0.06f, 1.0f, 0.3f}, cell, k++);
}

void SyntheticScene::addPeople(uint32_t seed, int walking, int sitting,
                               const std::vector<PersonSprite>& sprites)
{
    // Indices of the sprites of each posture; each person gets its own billboard.
    std::vector<size_t> standing, seated;
    for (size_t i = 0; i < sprites.size(); i++)
        (sprites[i].posture == PersonSprite::Posture::Sitting ? seated : standing).push_back(i);
    if ((walking > 0 && standing.empty()) || (sitting > 0 && seated.empty()))
        throw core::InputError(mrpt::format(
            "the scene has %d walking and %d sitting people, but the person cut-outs hold %zu "
            "standing and %zu sitting sprites",
            walking, sitting, standing.size(), seated.size()));

    // Instance ids after the furniture. Walkers on paths through the free floor; sitters at
    // the desk and on the side chair. All face the cameras' side of the room.
    const std::vector<std::vector<Eigen::Vector2f>> paths = {
        {{1.0f, 1.9f}, {5.0f, 1.9f}, {5.0f, 2.45f}, {1.0f, 2.45f}},
        {{4.8f, 1.6f}, {1.6f, 2.4f}},
        {{1.8f, 4.4f}, {4.2f, 4.4f}, {4.0f, 1.8f}},
    };
    const float speeds[3] = {1.1f, 0.7f, 1.4f};
    const Eigen::Vector2f seats[2] = {{2.85f, 3.95f}, {4.65f, 3.3f}};
    std::mt19937 rng(seed * 7717u + 13u);
    for (int i = 0; i < walking + sitting; i++)
    {
        PersonSpec spec;
        spec.viewer = cameraBase().head<2>().cast<float>();
        const bool walks = i < walking;
        const auto& pool = walks ? standing : seated;
        const PersonSprite& sprite = sprites[pool[(seed + static_cast<uint32_t>(i)) % pool.size()]];
        std::uniform_real_distribution<float> height(static_cast<float>(sprite.minHeight),
                                                     static_cast<float>(sprite.maxHeight));
        spec.height = height(rng);
        if (walks)
        {
            spec.kind = PersonSpec::Kind::Walking;
            spec.path = paths[static_cast<size_t>(i)];
            spec.speed = speeds[i];
            spec.phase = 1.7f * static_cast<float>(i);
        }
        else
        {
            spec.kind = PersonSpec::Kind::Sitting;
            spec.seat = seats[i - walking];
            spec.seatHeight = 0.47f;
            spec.phase = 0.9f * static_cast<float>(i);
        }
        spec.sprite = personSprites_.size();
        personSprites_.emplace_back(sprite.image, BillboardStyle{kPersonRelief, true});
        const uint16_t id = nextInstance_++;
        instanceClasses_[id] = voc::kPerson;
        people_.emplace_back(spec, id);
    }
}
}  // namespace smap::sim
