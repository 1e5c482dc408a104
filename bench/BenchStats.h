// Order statistics shared by the timing programs in bench/.
#pragma once

#include <algorithm>
#include <vector>

namespace smap::bench
{
/// The q-quantile (0 = min, 0.5 = median, 1 = max) by nearest rank; 0 for an empty set.
inline double quantile(std::vector<double> v, double q)
{
    if (v.empty())
        return 0.0;
    const auto k = static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
}

inline double median(std::vector<double> v)
{
    return quantile(std::move(v), 0.5);
}
}  // namespace smap::bench
