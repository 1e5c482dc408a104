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

void DynamicParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string&)
{
    const char* s = "dynamic";
    const std::string m = cfg.read_string(s, "mode", toString(mode));
    if (m == "off")
        mode = FilterMode::Off;
    else if (m == "paper")
        mode = FilterMode::Paper;
    else if (m == "strong")
        mode = FilterMode::Strong;
    else
        throw core::InputError(
            mrpt::format("[dynamic] mode = '%s' is not one of: off, paper, strong", m.c_str()));
    tau = cfg.read_double(s, "tau", tau);
    lk_window = cfg.read_int(s, "lk_window", lk_window);
    lk_levels = cfg.read_int(s, "lk_levels", lk_levels);
    essential_threshold = cfg.read_double(s, "essential_threshold", essential_threshold);
    essential_confidence = cfg.read_double(s, "essential_confidence", essential_confidence);
    match_ratio = cfg.read_double(s, "match_ratio", match_ratio);
    match_radius = cfg.read_double(s, "match_radius", match_radius);
    pnp_threshold = cfg.read_double(s, "pnp_threshold", pnp_threshold);
    ego_max_queries = cfg.read_int(s, "ego_max_queries", ego_max_queries);
    frame_gap = cfg.read_int(s, "frame_gap", frame_gap);
    ego_gate_translation = cfg.read_double(s, "ego_gate_translation", ego_gate_translation);
    ego_gate_rotation_deg = cfg.read_double(s, "ego_gate_rotation_deg", ego_gate_rotation_deg);
    strong_lk_window = cfg.read_int(s, "strong_lk_window", strong_lk_window);
    strong_lk_levels = cfg.read_int(s, "strong_lk_levels", strong_lk_levels);
    tau_min = cfg.read_double(s, "tau_min", tau_min);
    tau_sigmas = cfg.read_double(s, "tau_sigmas", tau_sigmas);
    depth_margin = cfg.read_double(s, "depth_margin", depth_margin);
    depth_ratio = cfg.read_double(s, "depth_ratio", depth_ratio);
    occlusion_margin = cfg.read_double(s, "occlusion_margin", occlusion_margin);
    region_radius = cfg.read_double(s, "region_radius", region_radius);
    region_depth = cfg.read_double(s, "region_depth", region_depth);
    region_min_neighbours = cfg.read_int(s, "region_min_neighbours", region_min_neighbours);
    isolated_fraction = cfg.read_double(s, "isolated_fraction", isolated_fraction);
    extraction_priority_above =
        cfg.read_double(s, "extraction_priority_above", extraction_priority_above);
    if (!(pnp_threshold > 0.0))
        throw core::InputError(
            mrpt::format("[dynamic] pnp_threshold = %g must be > 0", pnp_threshold));
    if (frame_gap < 1 || frame_gap > 30)
        throw core::InputError(
            mrpt::format("[dynamic] frame_gap = %d must be in [1, 30]", frame_gap));
    if (ego_max_queries != 0 && ego_max_queries < 20)
        throw core::InputError(mrpt::format(
            "[dynamic] ego_max_queries = %d must be 0 (all) or >= 20", ego_max_queries));
    if (!(ego_gate_translation >= 0.0) || !(ego_gate_rotation_deg >= 0.0))
        throw core::InputError(mrpt::format(
            "[dynamic] ego_gate_translation = %g and ego_gate_rotation_deg = %g must be >= 0",
            ego_gate_translation, ego_gate_rotation_deg));
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
    cfg.write(s, "pnp_threshold", pnp_threshold);
    cfg.write(s, "ego_max_queries", ego_max_queries);
    cfg.write(s, "ego_gate_translation", ego_gate_translation);
    cfg.write(s, "ego_gate_rotation_deg", ego_gate_rotation_deg);
    cfg.write(s, "frame_gap", frame_gap);
    cfg.write(s, "strong_lk_window", strong_lk_window);
    cfg.write(s, "strong_lk_levels", strong_lk_levels);
    cfg.write(s, "tau_min", tau_min);
    cfg.write(s, "tau_sigmas", tau_sigmas);
    cfg.write(s, "depth_margin", depth_margin);
    cfg.write(s, "depth_ratio", depth_ratio);
    cfg.write(s, "occlusion_margin", occlusion_margin);
    cfg.write(s, "region_radius", region_radius);
    cfg.write(s, "region_depth", region_depth);
    cfg.write(s, "region_min_neighbours", region_min_neighbours);
    cfg.write(s, "isolated_fraction", isolated_fraction);
    cfg.write(s, "extraction_priority_above", extraction_priority_above);
}
}  // namespace smap::dynamic
