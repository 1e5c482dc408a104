// The median the project reports everywhere (timings, residuals, depths): the upper median, the
// element at index size/2 once sorted, found in linear time.
#pragma once

#include <algorithm>
#include <vector>

namespace smap::core
{
/// The upper median of `v` (reorders it); `ifEmpty` when `v` is empty.
template <typename T>
T upperMedianInPlace(std::vector<T>& v, T ifEmpty = T{})
{
    if (v.empty())
        return ifEmpty;
    const auto mid =
        v.begin() + static_cast<typename std::vector<T>::difference_type>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

/// The same on a copy.
template <typename T>
T upperMedian(std::vector<T> v, T ifEmpty = T{})
{
    return upperMedianInPlace(v, ifEmpty);
}
}  // namespace smap::core
