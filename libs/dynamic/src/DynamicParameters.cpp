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
        case FilterMode::Strong:
            return "strong";
    }
    return "off";
}

core::OptionFields DynamicParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "dynamic");
    f.addEnum(
         "mode", mode,
         {{"off", FilterMode::Off}, {"paper", FilterMode::Paper}, {"strong", FilterMode::Strong}})
        .add("tau", tau)
        .add("lk_window", lk_window)
        .add("lk_levels", lk_levels)
        .add("essential_threshold", essential_threshold)
        .add("essential_confidence", essential_confidence)
        .add("match_ratio", match_ratio)
        .add("match_radius", match_radius)
        .add("pnp_threshold", pnp_threshold)
        .add("ego_max_queries", ego_max_queries)
        .add("ego_gate_translation", ego_gate_translation)
        .add("ego_gate_rotation_deg", ego_gate_rotation_deg)
        .add("ego_gate_min_support", ego_gate_min_support)
        .add("frame_gap_s", frame_gap_s)
        .add("strong_lk_window", strong_lk_window)
        .add("strong_lk_levels", strong_lk_levels)
        .add("tau_min", tau_min)
        .add("tau_sigmas", tau_sigmas)
        .add("depth_margin", depth_margin)
        .add("depth_ratio", depth_ratio)
        .add("occlusion_margin", occlusion_margin)
        .add("region_radius", region_radius)
        .add("region_depth", region_depth)
        .add("region_min_neighbours", region_min_neighbours)
        .add("isolated_fraction", isolated_fraction)
        .add("extraction_priority_above", extraction_priority_above);
    return f;
}

void DynamicParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string& section)
{
    fields(section).load(cfg);
    validateFlowAndMatching();
    validateStrongMode();
}

void DynamicParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                         const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<DynamicParameters*>(this)->fields(section).save(cfg);
}

void DynamicParameters::validateStrongMode() const
{
    if (!(pnp_threshold > 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] pnp_threshold = %g must be > 0", pnp_threshold));
    if (!(frame_gap_s >= 0.0 && frame_gap_s <= 1.0))
        throw core::InputError(
            mrpt::format("[dynamic] frame_gap_s = %g must be in [0, 1] s", frame_gap_s));
    if (ego_max_queries != 0 && ego_max_queries < 20)
        throw core::InputError(mrpt::format(
            "[dynamic] ego_max_queries = %d must be 0 (all) or >= 20", ego_max_queries));
    if (!(ego_gate_translation >= 0.0) || !(ego_gate_rotation_deg >= 0.0))
        throw core::InputError(mrpt::format(
            "[dynamic] ego_gate_translation = %g and ego_gate_rotation_deg = %g must be >= 0",
            ego_gate_translation, ego_gate_rotation_deg));
    if (ego_gate_min_support < 0)
        throw core::InputError(
            mrpt::format("[dynamic] ego_gate_min_support = %d must be >= 0", ego_gate_min_support));
    if (!(tau_min > 0.0 && tau_min <= tau))
        throw core::InputError(
            mrpt::format("[dynamic] tau_min = %g must be in (0, tau = %g]", tau_min, tau));
    if (!(tau_sigmas > 0.0))
        throw core::InputError(mrpt::format("[dynamic] tau_sigmas = %g must be > 0", tau_sigmas));
    if (!(depth_margin > 0.0) || !(depth_ratio >= 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] depth_margin = %g must be > 0 and depth_ratio = %g >= 0",
                         depth_margin, depth_ratio));
    if (!(occlusion_margin > 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] occlusion_margin = %g must be > 0", occlusion_margin));
    if (!(extraction_priority_above >= 0.0 && extraction_priority_above <= 1.0))
        throw core::InputError(
            mrpt::format("[dynamic] extraction_priority_above = %g must be in [0, 1]",
                         extraction_priority_above));
    if (!(isolated_fraction >= 0.0 && isolated_fraction < 1.0))
        throw core::InputError(
            mrpt::format("[dynamic] isolated_fraction = %g must be in [0, 1)", isolated_fraction));
    if (!(region_radius >= 0.0) || !(region_depth > 0.0) || region_min_neighbours < 1)
        throw core::InputError(
            mrpt::format("[dynamic] need region_radius >= 0 (%g), region_depth > 0 (%g), "
                         "region_min_neighbours >= 1 (%d)",
                         region_radius, region_depth, region_min_neighbours));
}

void DynamicParameters::validateFlowAndMatching() const
{
    if (!(match_radius > 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] match_radius = %g must be > 0", match_radius));
    if (!(tau > 0.0))
        throw core::InputError(mrpt::format("[dynamic] tau = %g must be > 0", tau));
    for (const auto& [key, value] : {std::pair<const char*, int>{"lk_window", lk_window},
                                     {"strong_lk_window", strong_lk_window}})
        if (value < 5 || value % 2 == 0)
            throw core::InputError(
                mrpt::format("[dynamic] %s = %d must be odd and >= 5", key, value));
    for (const auto& [key, value] : {std::pair<const char*, int>{"lk_levels", lk_levels},
                                     {"strong_lk_levels", strong_lk_levels}})
        if (value < 0 || value > 6)
            throw core::InputError(mrpt::format("[dynamic] %s = %d must be in [0, 6]", key, value));
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

}  // namespace smap::dynamic
