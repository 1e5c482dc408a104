#include "smap/sim/SceneObject.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace smap::sim
{
void addRectangle(SceneObject& obj, const Eigen::Vector3f& origin, const Eigen::Vector3f& edgeU,
                  const Eigen::Vector3f& edgeV, float cellSize, uint32_t seed)
{
    const int nu = std::max(1, static_cast<int>(std::ceil(edgeU.norm() / cellSize)));
    const int nv = std::max(1, static_cast<int>(std::ceil(edgeV.norm() / cellSize)));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> offset(0.0f, 0.5f);
    for (int i = 0; i < nu; i++)
    {
        for (int j = 0; j < nv; j++)
        {
            const Eigen::Vector3f a = origin + edgeU * (static_cast<float>(i) / nu) +
                                      edgeV * (static_cast<float>(j) / nv);
            const Eigen::Vector3f du = edgeU / static_cast<float>(nu),
                                  dv = edgeV / static_cast<float>(nv);
            TexturedQuad q;
            q.corners = {a, a + du, a + du + dv, a + dv};
            // A window of half the texture per cell, its size scaled with the cell's aspect.
            const float u0 = offset(rng), v0 = offset(rng);
            q.uv = {u0, v0, u0 + 0.5f,
                    v0 + 0.5f * std::min(1.0f, dv.norm() / std::max(1e-3f, du.norm()))};
            obj.quads.push_back(q);
        }
    }
}

void addBox(SceneObject& obj, const Eigen::Vector3f& centre, const Eigen::Vector3f& size,
            float cellSize, uint32_t seed)
{
    const Eigen::Vector3f h = 0.5f * size;
    const Eigen::Vector3f lo = centre - h;
    const Eigen::Vector3f ex(size.x(), 0, 0), ey(0, size.y(), 0), ez(0, 0, size.z());
    addRectangle(obj, lo, ex, ez, cellSize, seed + 1);       // -y face
    addRectangle(obj, lo + ey, ex, ez, cellSize, seed + 2);  // +y face
    addRectangle(obj, lo, ey, ez, cellSize, seed + 3);       // -x face
    addRectangle(obj, lo + ex, ey, ez, cellSize, seed + 4);  // +x face
    addRectangle(obj, lo, ex, ey, cellSize, seed + 5);       // bottom
    addRectangle(obj, lo + ez, ex, ey, cellSize, seed + 6);  // top
}
}  // namespace smap::sim
