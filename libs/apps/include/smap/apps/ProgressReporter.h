// Progress of a long run: on a terminal one line rewritten in place (frames done, frames/s,
// ETA when the total is known); otherwise a plain log line every few seconds.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <chrono>
#include <optional>
#include <ostream>
#include <string>

namespace smap::apps
{
class ProgressReporter
{
public:
    /// `terminal`: the stream the in-place line goes to, or null for log lines through `log`.
    ProgressReporter(std::optional<size_t> total, std::ostream* terminal,
                     mrpt::system::COutputLogger& log);

    /// After each frame; `extra` is appended (e.g. "2 lost, 14 keyframes").
    void update(size_t done, const std::string& extra);
    /// Clears the in-place line.
    void finish();

    /// "frame 120 / 1000  31.2 frames/s  ETA 28 s" (ETA only with a total).
    static std::string line(size_t done, std::optional<size_t> total, double seconds);

private:
    std::optional<size_t> total_;
    std::ostream* terminal_;
    mrpt::system::COutputLogger& log_;
    std::chrono::steady_clock::time_point start_;
    double lastReport_ = -1.0;
    size_t lastLength_ = 0;
};
}  // namespace smap::apps
