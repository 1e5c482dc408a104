// Fuzzes the images of a one-frame TUM folder through the real TumSource: whatever bytes the
// colour and depth files hold, reading gives a frame of the configured size or a skipped frame
// with a reason - never a crash, a leak, a hang or a sanitizer report.
//
// Input: a 4-byte little-endian length L, L bytes of colour image, then the depth image's bytes
// (seeds in tests/fuzz/seeds/fuzz_tum_frame: PNG and JPEG colour, 16-bit PNG depth, 64x48).
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>
#include <variant>

#include "FuzzFolder.h"
#include "smap/core/InputError.h"
#include "smap/io/TumSource.h"

namespace
{
const smap::fuzz::FuzzFolder& folder()
{
    static const smap::fuzz::FuzzFolder dir("smap-fuzz-tum-frame");  // one per process
    return dir;
}

smap::io::FrameSourceParameters parameters()
{
    smap::io::FrameSourceParameters p;
    smap::core::PinholeCamera cam;
    cam.width = 64;
    cam.height = 48;
    cam.fx = cam.fy = 60.0;
    cam.cx = 31.5;
    cam.cy = 23.5;
    p.camera = cam;
    return p;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    const auto& dir = folder();
    std::filesystem::create_directories(dir / "rgb");
    std::filesystem::create_directories(dir / "depth");
    std::ofstream(dir / "associations.txt") << "1.0 rgb/0.png 1.0 depth/0.png\n";
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 4)
        return 0;
    const size_t colourBytes =
        std::min<size_t>(size - 4, data[0] | (data[1] << 8) | (data[2] << 16) |
                                       (static_cast<size_t>(data[3]) << 24));
    const auto& dir = folder();
    dir.write("rgb/0.png", data + 4, colourBytes);
    dir.write("depth/0.png", data + 4 + colourBytes, size - 4 - colourBytes);
    smap::io::TumSource source(dir.str(), parameters());
    source.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    const auto read = source.read();
    if (!read)
        __builtin_trap();  // the folder lists one frame
    if (const auto* frame = std::get_if<smap::core::RgbdFrame>(&*read))
        frame->validate();  // a frame that is delivered is whole
    else if (std::get<smap::io::SkippedFrame>(*read).reason.empty())
        __builtin_trap();  // a skipped frame says why
    if (source.read().has_value())
        __builtin_trap();
    return 0;
}
