#include "smap/apps/ProgressReporter.h"

#include <mrpt/core/format.h>

#include <algorithm>

namespace smap::apps
{
ProgressReporter::ProgressReporter(std::optional<size_t> total, std::ostream* terminal,
                                   mrpt::system::COutputLogger& log)
    : total_(total), terminal_(terminal), log_(log), start_(std::chrono::steady_clock::now())
{
}

std::string ProgressReporter::line(size_t done, std::optional<size_t> total, double seconds)
{
    const double fps = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
    if (total && *total > 0)
    {
        const size_t left = *total > done ? *total - done : 0;
        const std::string eta =
            fps > 0.0 ? mrpt::format("%.0f s", static_cast<double>(left) / fps) : "?";
        return mrpt::format("frame %zu / %zu  %.1f frames/s  ETA %s", done, *total, fps,
                            eta.c_str());
    }
    return mrpt::format("frame %zu  %.1f frames/s", done, fps);
}

void ProgressReporter::update(size_t done, const std::string& extra)
{
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double period = terminal_ ? 0.25 : 5.0;
    if (lastReport_ >= 0.0 && t - lastReport_ < period)
        return;
    lastReport_ = t;
    std::string text = line(done, total_, t);
    if (!extra.empty())
        text += "  (" + extra + ")";
    if (terminal_)
    {
        const size_t pad = lastLength_ > text.size() ? lastLength_ - text.size() : 0;
        *terminal_ << "\r" << text << std::string(pad, ' ') << std::flush;
        lastLength_ = text.size();
    }
    else
        log_.logStr(mrpt::system::LVL_INFO, text);
}

void ProgressReporter::finish()
{
    if (terminal_ && lastLength_ > 0)
        *terminal_ << "\r" << std::string(lastLength_, ' ') << "\r" << std::flush;
    lastLength_ = 0;
}
}  // namespace smap::apps
