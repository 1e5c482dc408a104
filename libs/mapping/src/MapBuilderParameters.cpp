#include "smap/mapping/MapBuilderParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::mapping
{
void MapBuilderParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                              const std::string&)
{
    const char* s = "map";
    points_map = cfg.read_bool(s, "points_map", points_map);
    octomap = cfg.read_bool(s, "octomap", octomap);
    contribution_voxel = cfg.read_double(s, "contribution_voxel", contribution_voxel);
    reanchor_translation = cfg.read_double(s, "reanchor_translation", reanchor_translation);
    reanchor_rotation_deg = cfg.read_double(s, "reanchor_rotation_deg", reanchor_rotation_deg);
    prune_free_points = cfg.read_bool(s, "prune_free_points", prune_free_points);
    prune_near_movers = cfg.read_double(s, "prune_near_movers", prune_near_movers);
    if (!(prune_near_movers >= 0.0 && prune_near_movers <= 2.0))
        throw core::InputError(mrpt::format(
            "[map] prune_near_movers = %g must be in [0, 2] m (0: off)", prune_near_movers));
    confirm_near_movers = cfg.read_int(s, "confirm_near_movers", confirm_near_movers);
    confirm_radius = cfg.read_double(s, "confirm_radius", confirm_radius);
    confirm_span_s = cfg.read_double(s, "confirm_span_s", confirm_span_s);
    confirm_clear_distance = cfg.read_double(s, "confirm_clear_distance", confirm_clear_distance);
    if (!(confirm_clear_distance >= 0.0 && confirm_clear_distance <= 2.0))
        throw core::InputError(
            mrpt::format("[map] confirm_clear_distance = %g must be in [0, 2] m (0: off)",
                         confirm_clear_distance));
    see_through_margin = cfg.read_double(s, "see_through_margin", see_through_margin);
    if (!(see_through_margin >= 0.0 && see_through_margin <= 2.0))
        throw core::InputError(mrpt::format(
            "[map] see_through_margin = %g must be in [0, 2] m (0: off)", see_through_margin));
    see_through_majority = cfg.read_bool(s, "see_through_majority", see_through_majority);
    loadMovableBody(cfg);
    if (!(confirm_span_s >= 0.0))
        throw core::InputError(
            mrpt::format("[map] confirm_span_s = %g must be >= 0 s", confirm_span_s));
    if (confirm_near_movers < 0 || confirm_near_movers > 16)
        throw core::InputError(mrpt::format(
            "[map] confirm_near_movers = %d must be in [0, 16] keyframes (0 or 1: off)",
            confirm_near_movers));
    if (!(confirm_radius > 0.0 && confirm_radius <= 1.0))
        throw core::InputError(
            mrpt::format("[map] confirm_radius = %g must be in (0, 1] m", confirm_radius));
    if (!(contribution_voxel >= 0.0 && contribution_voxel <= 1.0))
        throw core::InputError(
            mrpt::format("[map] contribution_voxel = %g must be in [0, 1] m (0: no thinning)",
                         contribution_voxel));
    if (!(reanchor_translation >= 0.0) || !(reanchor_rotation_deg >= 0.0))
        throw core::InputError(mrpt::format(
            "[map] reanchor_translation = %g and reanchor_rotation_deg = %g must be >= 0",
            reanchor_translation, reanchor_rotation_deg));
    pointsMap.loadFromConfigFile(cfg, "points_map");
    octoMap.loadFromConfigFile(cfg, "octomap");
}

void MapBuilderParameters::loadMovableBody(const mrpt::config::CConfigFileBase& cfg)
{
    const char* s = "map";
    movable_body_radius = cfg.read_double(s, "movable_body_radius", movable_body_radius);
    movable_body_erosion = cfg.read_int(s, "movable_body_erosion", movable_body_erosion);
    movable_body_prior = cfg.read_double(s, "movable_body_prior", movable_body_prior);
    if (!(movable_body_radius >= 0.0 && movable_body_radius <= 1.0))
        throw core::InputError(mrpt::format(
            "[map] movable_body_radius = %g must be in [0, 1] m (0: off)", movable_body_radius));
    if (movable_body_erosion < 0 || movable_body_erosion > 100)
        throw core::InputError(mrpt::format(
            "[map] movable_body_erosion = %d must be in [0, 100] px", movable_body_erosion));
    if (!(movable_body_prior >= 0.0))
        throw core::InputError(mrpt::format(
            "[map] movable_body_prior = %g must be >= 0 (above 1: no class)", movable_body_prior));
}

void MapBuilderParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                            const std::string&) const
{
    const char* s = "map";
    cfg.write(s, "points_map", points_map);
    cfg.write(s, "octomap", octomap);
    cfg.write(s, "contribution_voxel", contribution_voxel);
    cfg.write(s, "reanchor_translation", reanchor_translation);
    cfg.write(s, "reanchor_rotation_deg", reanchor_rotation_deg);
    cfg.write(s, "prune_free_points", prune_free_points);
    cfg.write(s, "prune_near_movers", prune_near_movers);
    cfg.write(s, "confirm_near_movers", confirm_near_movers);
    cfg.write(s, "confirm_radius", confirm_radius);
    cfg.write(s, "confirm_span_s", confirm_span_s);
    cfg.write(s, "confirm_clear_distance", confirm_clear_distance);
    cfg.write(s, "see_through_margin", see_through_margin);
    cfg.write(s, "see_through_majority", see_through_majority);
    cfg.write(s, "movable_body_radius", movable_body_radius);
    cfg.write(s, "movable_body_erosion", movable_body_erosion);
    cfg.write(s, "movable_body_prior", movable_body_prior);
    pointsMap.saveToConfigFile(cfg, "points_map");
    octoMap.saveToConfigFile(cfg, "octomap");
}
}  // namespace smap::mapping
