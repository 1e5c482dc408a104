// Fuzzes the TUM text parsers (image lists, associations, trajectories): any input must either
// parse or raise core::InputError - never crash, hang or trip a sanitizer.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "smap/core/InputError.h"
#include "smap/io/TumTextFormats.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try
    {
        std::istringstream in(text);
        smap::io::parseTumList(in, "fuzz");
    }
    catch (const smap::core::InputError&)
    {
    }
    try
    {
        std::istringstream in(text);
        smap::io::parseTumAssociations(in, "fuzz");
    }
    catch (const smap::core::InputError&)
    {
    }
    try
    {
        std::istringstream in(text);
        const auto t = smap::io::parseTumTrajectory(in, "fuzz");
        // Whatever parsed must format and parse back to the same number of poses.
        std::string out;
        for (const auto& p : t)
            out += smap::io::formatTumPose(p) + "\n";
        std::istringstream back(out);
        if (smap::io::parseTumTrajectory(back, "fuzz-roundtrip").size() != t.size())
            __builtin_trap();
    }
    catch (const smap::core::InputError&)
    {
    }
    return 0;
}
