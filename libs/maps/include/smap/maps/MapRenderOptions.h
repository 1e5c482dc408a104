// How the semantic maps draw themselves (getVisualizationInto, MapSnapshot): section
// "<map>_renderOpts" in CMultiMetricMap configurations.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace smap::maps
{
struct MapRenderOptions : public mrpt::config::CLoadableOptions
{
    bool colour_by_class = true;  ///< else by the RGB the map holds
    double point_size = 3.0;      ///< pixels

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};
}  // namespace smap::maps
