// Fuzzes rawlogs through the real RawlogSource: truncated, bit-flipped or random bytes (seeds:
// pieces of the project's sample recording, tests/fuzz/seeds/fuzz_rawlog) either read as frames
// and skipped frames, end early with the damage named, or raise core::InputError - never a
// crash, a leak, a hang or a sanitizer report. External images resolve into the sample's
// images folder, as for the sample itself.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <new>
#include <string>
#include <variant>

#include "FuzzFolder.h"
#include "smap/core/InputError.h"
#include "smap/io/RawlogSource.h"

namespace
{
const smap::fuzz::FuzzFolder& folder()
{
    static const smap::fuzz::FuzzFolder dir("smap-fuzz-rawlog");  // one per process
    return dir;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    std::filesystem::create_directory_symlink(
        std::string(SMAP_SOURCE_DIR) + "/rawlogs/sample_walking_xyz_Images",
        folder() / "fuzz_Images");
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const auto& dir = folder();
    dir.write("fuzz.rawlog", data, size);
    try
    {
        smap::io::RawlogSource source(dir / "fuzz.rawlog", {});
        source.setMinLoggingLevel(mrpt::system::LVL_ERROR);
        // A few frames are enough to reach every kind of entry; decoding more only slows down.
        constexpr int kMaxReads = 6;
        for (int i = 0; i < kMaxReads; i++)
        {
            const auto read = source.read();
            if (!read)
                break;
            if (const auto* frame = std::get_if<smap::core::RgbdFrame>(&*read))
                frame->validate();
            else if (std::get<smap::io::SkippedFrame>(*read).reason.empty())
                __builtin_trap();
        }
    }
    catch (const smap::core::InputError&)
    {
    }
    return 0;
}
