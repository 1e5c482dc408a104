#include "smap/core/TimestampAssociation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace smap::core
{
std::vector<AssociatedPair> associateTimestamps(const std::vector<double>& first,
                                                const std::vector<double>& second,
                                                double maxDifference, double offset)
{
    // Indices of `second` sorted by shifted time, to find each window by binary search.
    std::vector<size_t> order(second.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return second[a] < second[b]; });
    std::vector<double> shifted(order.size());
    for (size_t k = 0; k < order.size(); k++)
        shifted[k] = second[order[k]] + offset;

    std::vector<AssociatedPair> candidates;
    for (size_t i = 0; i < first.size(); i++)
    {
        const double t = first[i];
        if (!std::isfinite(t))
            continue;
        auto it = std::lower_bound(shifted.begin(), shifted.end(), t - maxDifference);
        for (; it != shifted.end() && *it <= t + maxDifference; ++it)
        {
            const double dt = std::abs(t - *it);
            if (dt < maxDifference)
            {
                const auto k = static_cast<size_t>(it - shifted.begin());
                candidates.push_back({i, order[k], dt});
            }
        }
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const AssociatedPair& a, const AssociatedPair& b)
              { return std::tie(a.dt, a.first, a.second) < std::tie(b.dt, b.first, b.second); });

    std::vector<bool> usedFirst(first.size(), false);
    std::vector<bool> usedSecond(second.size(), false);
    std::vector<AssociatedPair> matches;
    for (const auto& c : candidates)
    {
        if (usedFirst[c.first] || usedSecond[c.second])
            continue;
        usedFirst[c.first] = true;
        usedSecond[c.second] = true;
        matches.push_back(c);
    }
    std::sort(matches.begin(), matches.end(),
              [](const AssociatedPair& a, const AssociatedPair& b) { return a.first < b.first; });
    return matches;
}
}  // namespace smap::core
