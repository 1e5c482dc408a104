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

void SyntheticScene::addPerson(PersonSpec spec, const PersonSprite& sprite)
{
    spec.sprite = personSprites_.size();
    personSprites_.emplace_back(sprite.image, BillboardStyle{kPersonRelief, true});
    const uint16_t id = nextInstance_++;
    instanceClasses_[id] = voc::kPerson;
    people_.emplace_back(spec, id);
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
        addPerson(spec, sprite);
    }
}
namespace
{
constexpr float kOuterW = 16.0f, kOuterD = 10.0f, kCorridor = 2.0f, kCorridorHeight = 2.6f;
}  // namespace

LoopPath SyntheticScene::loopPath()
{
    LoopPath p;
    const double half = 0.5 * kCorridor;
    p.min = {half, half};
    p.max = {kOuterW - half, kOuterD - half};
    p.cornerRadius = 0.6;
    p.height = 1.4;
    p.speed = 1.0;
    return p;
}

SyntheticScene SyntheticScene::makeCorridorLoop(uint32_t seed, int walking,
                                                const std::vector<PersonSprite>& sprites)
{
    if (walking < 0 || walking > 3)
        throw std::invalid_argument(mrpt::format("makeCorridorLoop: %d walking (0-3)", walking));
    SyntheticScene s;
    s.addCorridorWalls(seed);
    s.addCorridorFurniture(seed);
    s.addCorridorPeople(seed, walking, sprites);
    return s;
}

void SyntheticScene::addCorridorWalls(uint32_t seed)
{
    uint32_t k = seed * 2000u + 7u;
    const int ts = 512;
    const int floorTex = addTexture(makeTexture(TextureKind::Carpet, ts, k++));
    const int ceilingTex = addTexture(makeTexture(TextureKind::Paint, ts, k++));
    const float cell = 0.9f, W = kOuterW, D = kOuterD, H = kCorridorHeight, c = kCorridor;
    addRectangle(addObject("floor", voc::kBackground, floorTex), {0, 0, 0}, {W, 0, 0}, {0, D, 0},
                 cell, k++);
    addRectangle(addObject("ceiling", voc::kBackground, ceilingTex), {0, 0, H}, {W, 0, 0},
                 {0, D, 0}, cell, k++);
    // Walls in panels of about 2 m, each its own texture, one in three painted: outer walls,
    // then the inner block.
    const TextureKind kinds[] = {TextureKind::Noise, TextureKind::Paint, TextureKind::Tiles,
                                 TextureKind::Wood,  TextureKind::Paint, TextureKind::Noise};
    int panel = 0;
    auto wall = [&](const Eigen::Vector3f& from, const Eigen::Vector3f& to)
    {
        const Eigen::Vector3f along = to - from;
        const int n = std::max(1, static_cast<int>(std::round(along.norm() / 2.0f)));
        for (int i = 0; i < n; ++i)
        {
            const int tex = addTexture(makeTexture(kinds[panel % 6], ts, k++));
            auto& o = addObject(mrpt::format("wall_panel_%d", panel++), voc::kBackground, tex);
            addRectangle(o, from + along * (static_cast<float>(i) / n), along / n, {0, 0, H}, cell,
                         k++);
        }
    };
    const Eigen::Vector3f o0(0, 0, 0), o1(W, 0, 0), o2(W, D, 0), o3(0, D, 0);
    const Eigen::Vector3f i0(c, c, 0), i1(W - c, c, 0), i2(W - c, D - c, 0), i3(c, D - c, 0);
    for (const auto& [a, b] :
         {std::pair{o0, o1}, {o1, o2}, {o2, o3}, {o3, o0}, {i0, i1}, {i1, i2}, {i2, i3}, {i3, i0}})
        wall(a, b);
}

void SyntheticScene::addCorridorFurniture(uint32_t seed)
{
    uint32_t k = seed * 3000u + 11u;
    const int ts = 512;
    const float cell = 0.9f, W = kOuterW, D = kOuterD, c = kCorridor;
    std::mt19937 rng(seed * 131u + 5u);
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    // Posters and doors on the walls, cabinets and plants standing against them: every 2.5 m
    // along each outer wall, alternating, with the inner walls' posters in between.
    int item = 0;
    auto along = [&](const Eigen::Vector2f& from, const Eigen::Vector2f& to,
                     const Eigen::Vector2f& inward, bool outer)
    {
        const Eigen::Vector2f d = to - from;
        const int n = static_cast<int>(d.norm() / 2.5f);
        for (int i = 1; i <= n; ++i)
        {
            const Eigen::Vector2f p =
                from + d * ((static_cast<float>(i) - 0.5f + 0.2f * jitter(rng)) / n);
            const bool thin = std::abs(d.x()) > std::abs(d.y());
            const int kind = (item++ + (outer ? 0 : 1)) % 4;
            const int tex = addTexture(
                makeTexture(kind == 2 ? TextureKind::Wood : TextureKind::Poster, ts, k++));
            const Eigen::Vector2f q = p + inward * (kind >= 2 ? 0.22f : 0.02f);
            const Eigen::Vector3f size = kind == 0   ? Eigen::Vector3f(0.9f, 0.04f, 0.7f)  // poster
                                         : kind == 1 ? Eigen::Vector3f(0.9f, 0.04f, 2.0f)  // door
                                         : kind == 2 ? Eigen::Vector3f(0.7f, 0.4f, 1.1f)  // cabinet
                                                     : Eigen::Vector3f(0.4f, 0.4f, 0.9f);  // plant
            const float z = kind == 0 ? 1.5f : 0.5f * size.z();
            const Eigen::Vector3f oriented =
                thin ? size : Eigen::Vector3f(size.y(), size.x(), size.z());
            const uint8_t cls = kind == 3 ? voc::kPottedPlant : voc::kBackground;
            addBox(addObject(mrpt::format("corridor_item_%d", item), cls, tex), {q.x(), q.y(), z},
                   oriented, cell, k++);
        }
    };
    along({0, 0}, {W, 0}, {0, 1}, true);
    along({W, 0}, {W, D}, {-1, 0}, true);
    along({W, D}, {0, D}, {0, -1}, true);
    along({0, D}, {0, 0}, {1, 0}, true);
    along({c, c}, {W - c, c}, {0, -1}, false);
    along({W - c, c}, {W - c, D - c}, {1, 0}, false);
    along({W - c, D - c}, {c, D - c}, {0, 1}, false);
    along({c, D - c}, {c, c}, {-1, 0}, false);
}

std::vector<size_t> SyntheticScene::standingSprites(const std::vector<PersonSprite>& sprites,
                                                    int walking)
{
    std::vector<size_t> standing;
    for (size_t i = 0; i < sprites.size(); i++)
        if (sprites[i].posture != PersonSprite::Posture::Sitting)
            standing.push_back(i);
    if (walking > 0 && standing.empty())
        throw core::InputError(mrpt::format(
            "the scene has %d walking people, but the person cut-outs hold no standing sprite",
            walking));
    return standing;
}

void SyntheticScene::addCorridorPeople(uint32_t seed, int walking,
                                       const std::vector<PersonSprite>& sprites)
{
    const std::vector<size_t> standing = standingSprites(sprites, walking);
    // Up and down the middle of a straight stretch of the corridor beside the camera's path
    // (not at the corners, where the camera would turn into them), facing the end of it the
    // camera comes from.
    const float h = 0.5f * kCorridor;
    const std::vector<std::vector<Eigen::Vector2f>> paths = {
        {{2.8f, h + 0.6f}, {6.5f, h + 0.6f}},
        {{kOuterW - h - 0.6f, 4.0f}, {kOuterW - h - 0.6f, 7.5f}},
        {{12.0f, kOuterD - h - 0.6f}, {5.0f, kOuterD - h - 0.6f}},
    };
    const std::vector<Eigen::Vector2f> viewers = {
        {0.0f, h}, {kOuterW - h, 0.0f}, {kOuterW, kOuterD - h}};
    std::mt19937 rng(seed * 7717u + 29u);
    for (int i = 0; i < walking; i++)
    {
        const PersonSprite& sprite =
            sprites[standing[(seed + static_cast<uint32_t>(i)) % standing.size()]];
        std::uniform_real_distribution<float> height(static_cast<float>(sprite.minHeight),
                                                     static_cast<float>(sprite.maxHeight));
        PersonSpec spec;
        spec.kind = PersonSpec::Kind::Walking;
        spec.viewer = viewers[static_cast<size_t>(i)];
        spec.height = height(rng);
        spec.path = paths[static_cast<size_t>(i)];
        spec.speed = 0.9f + 0.2f * static_cast<float>(i);
        spec.phase = 2.3f * static_cast<float>(i);
        addPerson(spec, sprite);
    }
}
}  // namespace smap::sim
