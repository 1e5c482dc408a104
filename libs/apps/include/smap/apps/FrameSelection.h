// A set of frame indices given on the command line: "all", or a comma-separated list of
// indices and inclusive ranges ("0,50-60,120").
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace smap::apps
{
class FrameSelection
{
public:
    FrameSelection() = default;  ///< selects nothing

    /// Throws core::InputError naming `option` and the bad part of `text`.
    static FrameSelection parse(const std::string& text, const std::string& option);

    bool contains(size_t index) const;
    bool empty() const { return !all_ && ranges_.empty(); }

private:
    bool all_ = false;
    std::vector<std::pair<size_t, size_t>> ranges_;  ///< inclusive
};
}  // namespace smap::apps
