#include "smap/features/OrbParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

namespace smap::features
{
core::OptionFields OrbParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "orb");
    f.add("n_features", n_features)
        .add("scale_factor", scale_factor)
        .add("n_levels", n_levels)
        .add("fast_threshold", fast_threshold)
        .add("min_fast_threshold", min_fast_threshold)
        .add("cell_size", cell_size);
    return f;
}

void OrbParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                       const std::string& section)
{
    fields(section).load(cfg);
    if (n_features < 50)
        throw core::InputError(mrpt::format("[orb] n_features = %d must be >= 50", n_features));
    if (!(scale_factor > 1.0 && scale_factor < 2.0))
        throw core::InputError(
            mrpt::format("[orb] scale_factor = %g must be in (1, 2)", scale_factor));
    if (n_levels < 1 || n_levels > 16)
        throw core::InputError(mrpt::format("[orb] n_levels = %d must be in [1, 16]", n_levels));
    if (min_fast_threshold < 1 || fast_threshold < min_fast_threshold)
        throw core::InputError(
            mrpt::format("[orb] need 1 <= min_fast_threshold (%d) <= fast_threshold (%d)",
                         min_fast_threshold, fast_threshold));
    if (cell_size < 10)
        throw core::InputError(mrpt::format("[orb] cell_size = %d must be >= 10", cell_size));
}

void OrbParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                     const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<OrbParameters*>(this)->fields(section).save(cfg);
}
}  // namespace smap::features
