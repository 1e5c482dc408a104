// Summary statistics of a set of errors, as the TUM RGB-D benchmark reports them.
#pragma once

#include <cstddef>
#include <vector>

namespace smap::eval
{
struct ErrorStatistics
{
    double rmse = 0.0;
    double mean = 0.0;
    double median = 0.0;  ///< middle value; mean of the two middle values for an even count
    double std = 0.0;     ///< population standard deviation (numpy.std), about the mean
    double min = 0.0;
    double max = 0.0;
    size_t count = 0;
};

/// Statistics of `errors`; all zero for an empty input.
ErrorStatistics computeStatistics(const std::vector<double>& errors);
}  // namespace smap::eval
