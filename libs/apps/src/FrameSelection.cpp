#include "smap/apps/FrameSelection.h"

#include <mrpt/core/format.h>

#include <cctype>
#include <sstream>

#include "smap/core/InputError.h"

namespace smap::apps
{
namespace
{
bool parseIndex(const std::string& s, size_t& value)
{
    if (s.empty() || s.size() > 12)
        return false;
    for (char c : s)
        if (!std::isdigit(static_cast<unsigned char>(c)))
            return false;
    value = std::stoul(s);
    return true;
}
}  // namespace

FrameSelection FrameSelection::parse(const std::string& text, const std::string& option)
{
    FrameSelection sel;
    if (text == "all")
    {
        sel.all_ = true;
        return sel;
    }
    std::istringstream in(text);
    std::string part;
    while (std::getline(in, part, ','))
    {
        const auto dash = part.find('-');
        size_t a = 0, b = 0;
        const bool ok = dash == std::string::npos
                            ? parseIndex(part, a) && parseIndex(part, b)
                            : parseIndex(part.substr(0, dash), a) &&
                                  parseIndex(part.substr(dash + 1), b) && a <= b;
        if (!ok)
            throw core::InputError(mrpt::format(
                "--%s '%s': '%s' is not a frame index or a range A-B (A <= B); use e.g. "
                "'all' or '0,50-60'",
                option.c_str(), text.c_str(), part.c_str()));
        sel.ranges_.emplace_back(a, b);
    }
    if (sel.ranges_.empty())
        throw core::InputError(
            mrpt::format("--%s '%s' selects no frame", option.c_str(), text.c_str()));
    return sel;
}

bool FrameSelection::contains(size_t index) const
{
    if (all_)
        return true;
    for (const auto& [a, b] : ranges_)
        if (index >= a && index <= b)
            return true;
    return false;
}
}  // namespace smap::apps
