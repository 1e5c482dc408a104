#include "smap/features/OrbParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::features
{
void OrbParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string&)
{
    const std::string s = "orb";
    n_features = cfg.read_int(s, "n_features", n_features);
    scale_factor = cfg.read_double(s, "scale_factor", scale_factor);
    n_levels = cfg.read_int(s, "n_levels", n_levels);
    fast_threshold = cfg.read_int(s, "fast_threshold", fast_threshold);
    min_fast_threshold = cfg.read_int(s, "min_fast_threshold", min_fast_threshold);
    cell_size = cfg.read_int(s, "cell_size", cell_size);
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

void OrbParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string&) const
{
    const std::string s = "orb";
    cfg.write(s, "n_features", n_features);
    cfg.write(s, "scale_factor", scale_factor);
    cfg.write(s, "n_levels", n_levels);
    cfg.write(s, "fast_threshold", fast_threshold);
    cfg.write(s, "min_fast_threshold", min_fast_threshold);
    cfg.write(s, "cell_size", cell_size);
}
}  // namespace smap::features
