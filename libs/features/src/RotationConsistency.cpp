#include "smap/features/RotationConsistency.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace smap::features
{
void RotationConsistency::add(size_t id, float angle_a, float angle_b)
{
    float d = angle_b - angle_a;
    if (d < 0.0F)
        d += 360.0F;
    int bin = static_cast<int>(std::lround(d * static_cast<float>(bins_) / 360.0F));
    if (bin >= bins_)
        bin = 0;
    hist_[static_cast<size_t>(std::clamp(bin, 0, bins_ - 1))].push_back(id);
}

std::vector<size_t> RotationConsistency::inconsistent() const
{
    std::array<int, 3> top{-1, -1, -1};
    auto count = [&](int b)
    { return b < 0 ? 0 : static_cast<int>(hist_[static_cast<size_t>(b)].size()); };
    for (int b = 0; b < bins_; ++b)
    {
        if (count(b) > count(top[0]))
        {
            top[2] = top[1];
            top[1] = top[0];
            top[0] = b;
        }
        else if (count(b) > count(top[1]))
        {
            top[2] = top[1];
            top[1] = b;
        }
        else if (count(b) > count(top[2]))
        {
            top[2] = b;
        }
    }
    const int maxCount = count(top[0]);
    if (count(top[1]) < 0.1 * maxCount)
        top[1] = top[2] = -1;
    else if (count(top[2]) < 0.1 * maxCount)
        top[2] = -1;
    std::vector<size_t> out;
    for (int b = 0; b < bins_; ++b)
    {
        if (b == top[0] || b == top[1] || b == top[2])
            continue;
        const auto& ids = hist_[static_cast<size_t>(b)];
        out.insert(out.end(), ids.begin(), ids.end());
    }
    return out;
}
}  // namespace smap::features
