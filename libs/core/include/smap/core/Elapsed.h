// Elapsed wall time since a steady-clock instant, and the calling thread's CPU time, for the
// timings components report.
#pragma once

#include <chrono>
#include <ctime>

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

/// CPU time the calling thread has used, in milliseconds: unlike wall time it leaves out the
/// time the thread waited for a lock or for a core taken by another thread.
inline double threadCpuMilliseconds()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}
}  // namespace smap::core
