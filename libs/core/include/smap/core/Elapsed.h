// Elapsed wall time since a steady-clock instant, for the timings components report.
#pragma once

#include <chrono>

namespace smap::core
{
using SteadyClock = std::chrono::steady_clock;

inline double secondsSince(SteadyClock::time_point t0)
{
    return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

inline double millisecondsSince(SteadyClock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
}
}  // namespace smap::core
