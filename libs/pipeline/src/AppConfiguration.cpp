#include "smap/pipeline/AppConfiguration.h"

#include "smap/core/TrackedConfig.h"

namespace smap::pipeline
{
void loadAppConfiguration(const CommandLine& cl,
                          const std::vector<mrpt::config::CLoadableOptions*>& params)
{
    core::TrackedConfig cfg;
    // Several --config files apply in order, later keys over earlier ones (a camera preset
    // plus a segmentation configuration, say).
    const auto files = cl.values("config");
    for (size_t i = 0; i < files.size(); i++)
    {
        if (i == 0)
            cfg.loadFile(files[i]);
        else
            cfg.mergeFile(files[i]);
    }
    for (const auto& s : cl.values("set"))
        cfg.applyOverride(s);
    for (auto* p : params)
        cfg.load(*p);
    cfg.ensureAllKeysUsed();
}
}  // namespace smap::pipeline
