#include "FrameHistory.h"

#include <algorithm>

namespace smap::dynamic
{
std::pair<int, int> DecisionCells::around(int cx, int cy, int radius) const
{
    int n = 0, nDynamic = 0;
    for (int y = std::max(0, cy - radius); y <= std::min(rows - 1, cy + radius); ++y)
    {
        for (int x = std::max(0, cx - radius); x <= std::min(cols - 1, cx + radius); ++x)
        {
            const size_t k =
                static_cast<size_t>(y) * static_cast<size_t>(cols) + static_cast<size_t>(x);
            n += all[k];
            nDynamic += dynamic[k];
        }
    }
    return {n, nDynamic};
}

DecisionCells DecisionCells::count(const features::FeatureSet& features,
                                   const std::vector<bool>& dynamic, int width, int height)
{
    DecisionCells c;
    c.cols = (width + kCell - 1) / kCell;
    c.rows = (height + kCell - 1) / kCell;
    c.all.assign(static_cast<size_t>(c.cols) * static_cast<size_t>(c.rows), 0);
    c.dynamic.assign(c.all.size(), 0);
    for (size_t i = 0; i < features.size() && i < dynamic.size(); ++i)
    {
        const int x =
            std::clamp(static_cast<int>(features.keypoints[i].pt.x) / kCell, 0, c.cols - 1);
        const int y =
            std::clamp(static_cast<int>(features.keypoints[i].pt.y) / kCell, 0, c.rows - 1);
        const auto k =
            static_cast<size_t>(y) * static_cast<size_t>(c.cols) + static_cast<size_t>(x);
        c.all[k]++;
        c.dynamic[k] += dynamic[i] ? 1 : 0;
    }
    return c;
}
}  // namespace smap::dynamic
