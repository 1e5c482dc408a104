#include "MoverVoxels.h"

#include <cmath>

#include "KeyFrameVoxels.h"

namespace smap::mapping
{
MoverVoxels::MoverVoxels(double edge) : edge_(edge) {}

int64_t MoverVoxels::key(double x, double y, double z) const
{
    const auto q = [this](double a) { return static_cast<int64_t>(std::floor(a / edge_)); };
    return voxelKey(q(x), q(y), q(z));
}

void MoverVoxels::add(const KeyFrameContribution& c)
{
    for (const auto& m : c.movers_cam)
    {
        double x = 0, y = 0, z = 0;
        c.T_world_cam.composePoint(m.x(), m.y(), m.z(), x, y, z);
        for (int dx = -1; dx <= 1; ++dx)
        {
            for (int dy = -1; dy <= 1; ++dy)
            {
                for (int dz = -1; dz <= 1; ++dz)
                    voxels_.insert(key(x + dx * edge_, y + dy * edge_, z + dz * edge_));
            }
        }
    }
}

bool MoverVoxels::near(const Eigen::Vector3f& p) const
{
    return voxels_.count(key(p.x(), p.y(), p.z())) > 0;
}
}  // namespace smap::mapping
