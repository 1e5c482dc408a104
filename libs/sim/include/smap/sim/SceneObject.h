// Geometry of the synthetic world: objects made of textured quads, with a class label (PASCAL
// VOC id) and an instance id. World frame: z up, floor at z = 0, metres.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace smap::sim
{
/// PASCAL VOC ids used by the generator.
namespace voc
{
constexpr uint8_t kBackground = 0;
constexpr uint8_t kChair = 9;
constexpr uint8_t kDiningTable = 11;
constexpr uint8_t kPerson = 15;
constexpr uint8_t kPottedPlant = 16;
constexpr uint8_t kSofa = 18;
constexpr uint8_t kTvMonitor = 20;
}  // namespace voc

struct TexturedQuad
{
    /// Corners in the object frame, in order around the quad.
    std::array<Eigen::Vector3f, 4> corners;
    /// Texture window (u0, v0, u1, v1) within [0, 1] used on this quad.
    Eigen::Vector4f uv{0.0f, 0.0f, 1.0f, 1.0f};
};

struct SceneObject
{
    std::string name;
    uint8_t classId = voc::kBackground;
    uint16_t instanceId = 0;  ///< unique per object in the world (0 = nothing rendered)
    int textureIndex = 0;     ///< into SyntheticScene::textures()
    std::vector<TexturedQuad> quads;
    mrpt::poses::CPose3D T_world_object;  ///< pose of the object in the world
};

/// Adds the 6 faces of an axis-aligned box (object frame) centred at `centre`. Large faces are
/// split into cells of about `cellSize` metres, each showing a different window of the texture
/// so the pattern does not repeat exactly.
void addBox(SceneObject& obj, const Eigen::Vector3f& centre, const Eigen::Vector3f& size,
            float cellSize, uint32_t seed);
/// Adds one rectangle spanned by `origin`, `origin + edgeU`, `origin + edgeU + edgeV`, split in
/// cells as addBox does.
void addRectangle(SceneObject& obj, const Eigen::Vector3f& origin, const Eigen::Vector3f& edgeU,
                  const Eigen::Vector3f& edgeV, float cellSize, uint32_t seed);
}  // namespace smap::sim
