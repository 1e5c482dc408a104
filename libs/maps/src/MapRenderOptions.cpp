#include "smap/maps/MapRenderOptions.h"

#include <mrpt/config/CConfigFileBase.h>

namespace smap::maps
{
void MapRenderOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                          const std::string& section)
{
    colour_by_class = cfg.read_bool(section, "colour_by_class", colour_by_class);
    point_size = cfg.read_double(section, "point_size", point_size);
}

void MapRenderOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                        const std::string& section) const
{
    cfg.write(section, "colour_by_class", colour_by_class);
    cfg.write(section, "point_size", point_size);
}
}  // namespace smap::maps
