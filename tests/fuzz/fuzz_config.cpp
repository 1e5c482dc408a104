// Fuzzes configuration loading: INI and YAML text, --set overrides and the parameter structs
// that read them. Bad text must end in core::InputError, never a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "smap/core/InputError.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/FrameSourceParameters.h"

namespace
{
void loadAll(smap::core::TrackedConfig& cfg)
{
    smap::io::FrameSourceParameters p;
    cfg.load(p);
    cfg.unusedKeys();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    for (int mode = 0; mode < 3; mode++)
    {
        try
        {
            smap::core::TrackedConfig cfg;
            if (mode == 0)
                cfg.loadText(text, "fuzz.ini");
            if (mode == 1)
                cfg.loadYamlText(text, "fuzz.yaml");
            if (mode == 2)
                cfg.applyOverride(text);
            loadAll(cfg);
        }
        catch (const smap::core::InputError&)
        {
        }
    }
    return 0;
}
