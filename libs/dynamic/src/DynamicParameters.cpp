#include "smap/dynamic/DynamicParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::dynamic
{
std::string toString(FilterMode m)
{
    switch (m)
    {
        case FilterMode::Off:
            return "off";
        case FilterMode::Paper:
            return "paper";
    }
    return "off";
}

void DynamicParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string&)
{
    const char* s = "dynamic";
    const std::string m = cfg.read_string(s, "mode", toString(mode));
    if (m == "off")
        mode = FilterMode::Off;
    else if (m == "paper")
        mode = FilterMode::Paper;
    else
        throw core::InputError(
            mrpt::format("[dynamic] mode = '%s' is not one of: off, paper", m.c_str()));
    tau = cfg.read_double(s, "tau", tau);
    lk_window = cfg.read_int(s, "lk_window", lk_window);
    lk_levels = cfg.read_int(s, "lk_levels", lk_levels);
    essential_threshold = cfg.read_double(s, "essential_threshold", essential_threshold);
    essential_confidence = cfg.read_double(s, "essential_confidence", essential_confidence);
    match_ratio = cfg.read_double(s, "match_ratio", match_ratio);
    match_radius = cfg.read_double(s, "match_radius", match_radius);
    if (!(match_radius > 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] match_radius = %g must be > 0", match_radius));
    if (!(tau > 0.0))
        throw core::InputError(mrpt::format("[dynamic] tau = %g must be > 0", tau));
    if (lk_window < 5 || lk_window % 2 == 0)
        throw core::InputError(
            mrpt::format("[dynamic] lk_window = %d must be odd and >= 5", lk_window));
    if (lk_levels < 0 || lk_levels > 6)
        throw core::InputError(
            mrpt::format("[dynamic] lk_levels = %d must be in [0, 6]", lk_levels));
    if (!(essential_threshold > 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] essential_threshold = %g must be > 0", essential_threshold));
    if (!(essential_confidence > 0.0 && essential_confidence < 1.0))
        throw core::InputError(mrpt::format("[dynamic] essential_confidence = %g must be in (0, 1)",
                                            essential_confidence));
    if (!(match_ratio > 0.0 && match_ratio <= 1.0))
        throw core::InputError(
            mrpt::format("[dynamic] match_ratio = %g must be in (0, 1]", match_ratio));
}

void DynamicParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                         const std::string&) const
{
    const char* s = "dynamic";
    cfg.write(s, "mode", toString(mode));
    cfg.write(s, "tau", tau);
    cfg.write(s, "lk_window", lk_window);
    cfg.write(s, "lk_levels", lk_levels);
    cfg.write(s, "essential_threshold", essential_threshold);
    cfg.write(s, "essential_confidence", essential_confidence);
    cfg.write(s, "match_ratio", match_ratio);
    cfg.write(s, "match_radius", match_radius);
}
}  // namespace smap::dynamic
