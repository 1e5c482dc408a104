#include "smap/apps/AppConfiguration.h"

#include <filesystem>
#include <memory>
#include <optional>

#include "smap/core/DataDirectory.h"
#include "smap/core/TrackedConfig.h"
#include "smap/io/InputPreset.h"

namespace smap::apps
{
namespace
{
/// Every --config file in order (later keys over earlier ones), then every --set, on top of
/// `base` (a preset's text) when there is one.
std::unique_ptr<core::TrackedConfig> assemble(const CommandLine& cl,
                                              const std::optional<io::InputPreset>& base)
{
    auto cfg = std::make_unique<core::TrackedConfig>();
    bool loaded = false;
    if (base)
    {
        cfg->loadText(base->text, base->source);
        loaded = true;
    }
    for (const auto& file : cl.values("config"))
    {
        if (loaded)
            cfg->mergeFile(file);
        else
            cfg->loadFile(file);
        loaded = true;
    }
    for (const auto& s : cl.values("set"))
        cfg->applyOverride(s);
    return cfg;
}
}  // namespace

void loadAppConfiguration(const CommandLine& cl,
                          const std::vector<mrpt::config::CLoadableOptions*>& params,
                          const std::string& input, mrpt::system::COutputLogger& log)
{
    auto cfg = assemble(cl, std::nullopt);
    if (!input.empty() && !cfg->sectionExists("camera"))
    {
        if (const auto preset = io::presetForInput(input))
        {
            // Said before loading: an error below may name the preset's file.
            log.logStr(mrpt::system::LVL_INFO,
                       "no [camera] configured and '" + input + "' is a folder: " + preset->reason +
                           ", so " + preset->source +
                           " applies under the given configuration (a [camera] of your own "
                           "replaces it)");
            cfg = assemble(cl, preset);
        }
    }
    for (auto* p : params)
        cfg->load(*p);
    cfg->ensureAllKeysUsed();
}

}  // namespace smap::apps
