// Timestamp association exactly as the TUM RGB-D tools (associate.py) do it.
#pragma once

#include <cstddef>
#include <vector>

namespace smap::core
{
struct AssociatedPair
{
    size_t first = 0;   ///< index into the first list
    size_t second = 0;  ///< index into the second list
    double dt = 0.0;    ///< |t_first - (t_second + offset)|
};

/// Greedy one-to-one association: every pair with |a - (b + offset)| < maxDifference (strict,
/// as TUM) is a candidate; candidates are taken by increasing |dt| (ties by first index, then
/// second), skipping those whose first or second is already used. The result is sorted by first
/// index. Inputs need not be sorted. O(n log n + candidates).
std::vector<AssociatedPair> associateTimestamps(const std::vector<double>& first,
                                                const std::vector<double>& second,
                                                double maxDifference, double offset = 0.0);
}  // namespace smap::core
