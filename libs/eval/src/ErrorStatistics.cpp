#include "smap/eval/ErrorStatistics.h"

#include <algorithm>
#include <cmath>

namespace smap::eval
{
ErrorStatistics computeStatistics(const std::vector<double>& errors)
{
    ErrorStatistics s;
    s.count = errors.size();
    if (errors.empty())
        return s;
    double sum = 0.0, sumSq = 0.0;
    for (double e : errors)
    {
        sum += e;
        sumSq += e * e;
    }
    const auto n = static_cast<double>(errors.size());
    s.mean = sum / n;
    s.rmse = std::sqrt(sumSq / n);
    double var = 0.0;
    for (double e : errors)
        var += (e - s.mean) * (e - s.mean);
    s.std = std::sqrt(var / n);
    std::vector<double> sorted(errors);
    std::sort(sorted.begin(), sorted.end());
    s.min = sorted.front();
    s.max = sorted.back();
    const size_t mid = sorted.size() / 2;
    s.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
    return s;
}
}  // namespace smap::eval
