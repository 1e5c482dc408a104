#include "smap/pipeline/AppConfiguration.h"

#include "smap/core/TrackedConfig.h"

namespace smap::pipeline
{
void loadAppConfiguration(const CommandLine& cl,
                          const std::vector<mrpt::config::CLoadableOptions*>& params)
{
    core::TrackedConfig cfg;
    if (const auto c = cl.value("config"))
        cfg.loadFile(*c);
    for (const auto& s : cl.values("set"))
        cfg.applyOverride(s);
    for (auto* p : params)
        cfg.load(*p);
    cfg.ensureAllKeysUsed();
}
}  // namespace smap::pipeline
