// Options of the ORB extractor ([orb] section), loaded once from the configuration.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include "smap/core/OptionFields.h"

namespace smap::features
{
struct OrbParameters : public mrpt::config::CLoadableOptions
{
    int n_features = 1000;       ///< features per frame, shared over the levels geometrically
    double scale_factor = 1.2;   ///< between pyramid levels
    int n_levels = 8;            ///< pyramid levels
    int fast_threshold = 20;     ///< FAST threshold tried first in every grid cell
    int min_fast_threshold = 7;  ///< retried in cells where the first finds nothing
    int cell_size = 35;          ///< grid cell edge (pixels of each level)

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [orb]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};
}  // namespace smap::features
