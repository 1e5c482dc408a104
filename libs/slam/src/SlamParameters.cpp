#include "smap/slam/SlamParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::slam
{
namespace
{
void requirePositive(double v, const char* section, const char* key)
{
    if (!(v > 0.0))
        throw core::InputError(mrpt::format("[%s] %s = %g must be > 0", section, key, v));
}
}  // namespace

void TrackerParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string&)
{
    const char* s = "tracking";
    virtual_baseline = cfg.read_double(s, "virtual_baseline", virtual_baseline);
    close_depth = cfg.read_double(s, "close_depth", close_depth);
    min_depth = cfg.read_double(s, "min_depth", min_depth);
    max_depth = cfg.read_double(s, "max_depth", max_depth);
    depth_edge_ratio = cfg.read_double(s, "depth_edge_ratio", depth_edge_ratio);
    init_min_points = cfg.read_int(s, "init_min_points", init_min_points);
    motion_search_radius = cfg.read_double(s, "motion_search_radius", motion_search_radius);
    local_search_radius = cfg.read_double(s, "local_search_radius", local_search_radius);
    min_matches_motion = cfg.read_int(s, "min_matches_motion", min_matches_motion);
    min_inliers = cfg.read_int(s, "min_inliers", min_inliers);
    min_inliers_after_relocalisation =
        cfg.read_int(s, "min_inliers_after_relocalisation", min_inliers_after_relocalisation);
    keyframe_max_frames = cfg.read_int(s, "keyframe_max_frames", keyframe_max_frames);
    keyframe_min_frames = cfg.read_int(s, "keyframe_min_frames", keyframe_min_frames);
    keyframe_ref_ratio = cfg.read_double(s, "keyframe_ref_ratio", keyframe_ref_ratio);
    revisit_radius = cfg.read_double(s, "revisit_radius", revisit_radius);
    relocalisation_candidates =
        cfg.read_int(s, "relocalisation_candidates", relocalisation_candidates);
    reanchor_after = cfg.read_int(s, "reanchor_after", reanchor_after);
    fallback_weight = cfg.read_double(s, "fallback_weight", fallback_weight);
    optimisation_rounds = cfg.read_int(s, "optimisation_rounds", optimisation_rounds);
    optimisation_iterations = cfg.read_int(s, "optimisation_iterations", optimisation_iterations);

    requirePositive(virtual_baseline, s, "virtual_baseline");
    requirePositive(close_depth, s, "close_depth");
    requirePositive(min_depth, s, "min_depth");
    if (!(max_depth > min_depth))
        throw core::InputError(mrpt::format("[tracking] max_depth = %g must be > min_depth = %g",
                                            max_depth, min_depth));
    requirePositive(motion_search_radius, s, "motion_search_radius");
    requirePositive(local_search_radius, s, "local_search_radius");
    requirePositive(init_min_points, s, "init_min_points");
    requirePositive(min_inliers, s, "min_inliers");
    requirePositive(keyframe_max_frames, s, "keyframe_max_frames");
    if (keyframe_min_frames < 0)
        throw core::InputError(
            mrpt::format("[tracking] keyframe_min_frames = %d must be >= 0", keyframe_min_frames));
    if (!(keyframe_ref_ratio > 0.0 && keyframe_ref_ratio <= 1.0))
        throw core::InputError(mrpt::format("[tracking] keyframe_ref_ratio = %g must be in (0, 1]",
                                            keyframe_ref_ratio));
    if (revisit_radius < 0.0)
        throw core::InputError(
            mrpt::format("[tracking] revisit_radius = %g must be >= 0", revisit_radius));
    requirePositive(relocalisation_candidates, s, "relocalisation_candidates");
    if (reanchor_after < 0)
        throw core::InputError(
            mrpt::format("[tracking] reanchor_after = %d must be >= 0", reanchor_after));
    if (!(fallback_weight >= 0.0 && fallback_weight <= 1.0))
        throw core::InputError(
            mrpt::format("[tracking] fallback_weight = %g must be in [0, 1]", fallback_weight));
    requirePositive(optimisation_rounds, s, "optimisation_rounds");
    requirePositive(optimisation_iterations, s, "optimisation_iterations");
}

void TrackerParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                         const std::string&) const
{
    const char* s = "tracking";
    cfg.write(s, "virtual_baseline", virtual_baseline);
    cfg.write(s, "close_depth", close_depth);
    cfg.write(s, "min_depth", min_depth);
    cfg.write(s, "max_depth", max_depth);
    cfg.write(s, "depth_edge_ratio", depth_edge_ratio);
    cfg.write(s, "init_min_points", init_min_points);
    cfg.write(s, "motion_search_radius", motion_search_radius);
    cfg.write(s, "local_search_radius", local_search_radius);
    cfg.write(s, "min_matches_motion", min_matches_motion);
    cfg.write(s, "min_inliers", min_inliers);
    cfg.write(s, "min_inliers_after_relocalisation", min_inliers_after_relocalisation);
    cfg.write(s, "keyframe_max_frames", keyframe_max_frames);
    cfg.write(s, "keyframe_min_frames", keyframe_min_frames);
    cfg.write(s, "keyframe_ref_ratio", keyframe_ref_ratio);
    cfg.write(s, "revisit_radius", revisit_radius);
    cfg.write(s, "relocalisation_candidates", relocalisation_candidates);
    cfg.write(s, "reanchor_after", reanchor_after);
    cfg.write(s, "fallback_weight", fallback_weight);
    cfg.write(s, "optimisation_rounds", optimisation_rounds);
    cfg.write(s, "optimisation_iterations", optimisation_iterations);
}

void LocalMappingParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                const std::string&)
{
    const char* s = "local_mapping";
    threaded = cfg.read_bool(s, "threaded", threaded);
    ba_max_keyframes = cfg.read_int(s, "ba_max_keyframes", ba_max_keyframes);
    ba_iterations = cfg.read_int(s, "ba_iterations", ba_iterations);
    ba_refine_iterations = cfg.read_int(s, "ba_refine_iterations", ba_refine_iterations);
    global_ba_iterations = cfg.read_int(s, "global_ba_iterations", global_ba_iterations);
    covisibility_min_weight = cfg.read_int(s, "covisibility_min_weight", covisibility_min_weight);
    fuse_neighbours = cfg.read_int(s, "fuse_neighbours", fuse_neighbours);
    keyframe_redundancy = cfg.read_double(s, "keyframe_redundancy", keyframe_redundancy);
    if (ba_iterations < 0 || ba_refine_iterations < 0)
        throw core::InputError(mrpt::format(
            "[local_mapping] ba_iterations = %d and ba_refine_iterations = %d must be >= 0",
            ba_iterations, ba_refine_iterations));
    if (global_ba_iterations < 0)
        throw core::InputError(mrpt::format(
            "[local_mapping] global_ba_iterations = %d must be >= 0", global_ba_iterations));
    if (ba_max_keyframes < 2)
        throw core::InputError(
            mrpt::format("[local_mapping] ba_max_keyframes = %d must be >= 2", ba_max_keyframes));
    requirePositive(covisibility_min_weight, s, "covisibility_min_weight");
    if (fuse_neighbours < 0)
        throw core::InputError(
            mrpt::format("[local_mapping] fuse_neighbours = %d must be >= 0", fuse_neighbours));
    if (!(keyframe_redundancy > 0.0 && keyframe_redundancy <= 1.0))
        throw core::InputError(mrpt::format(
            "[local_mapping] keyframe_redundancy = %g must be in (0, 1]", keyframe_redundancy));
}

void LocalMappingParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                              const std::string&) const
{
    const char* s = "local_mapping";
    cfg.write(s, "threaded", threaded);
    cfg.write(s, "ba_max_keyframes", ba_max_keyframes);
    cfg.write(s, "ba_iterations", ba_iterations);
    cfg.write(s, "ba_refine_iterations", ba_refine_iterations);
    cfg.write(s, "global_ba_iterations", global_ba_iterations);
    cfg.write(s, "covisibility_min_weight", covisibility_min_weight);
    cfg.write(s, "fuse_neighbours", fuse_neighbours);
    cfg.write(s, "keyframe_redundancy", keyframe_redundancy);
}
}  // namespace smap::slam
