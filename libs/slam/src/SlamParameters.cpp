#include "smap/slam/SlamParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

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

core::OptionFields TrackerParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "tracking");
    f.add("virtual_baseline", virtual_baseline)
        .add("close_depth", close_depth)
        .add("keyframe_new_points", keyframe_new_points)
        .add("min_depth", min_depth)
        .add("max_depth", max_depth)
        .add("depth_edge_ratio", depth_edge_ratio)
        .add("init_min_points", init_min_points)
        .add("motion_search_radius", motion_search_radius)
        .add("local_search_radius", local_search_radius)
        .add("min_matches_motion", min_matches_motion)
        .add("min_inliers", min_inliers)
        .add("min_inliers_after_relocalisation", min_inliers_after_relocalisation)
        .add("keyframe_max_interval_s", keyframe_max_interval_s)
        .add("keyframe_min_interval_s", keyframe_min_interval_s)
        .add("keyframe_ref_ratio", keyframe_ref_ratio)
        .add("revisit_radius", revisit_radius)
        .add("revisit_max_age_s", revisit_max_age_s)
        .add("carried_search_s", carried_search_s)
        .add("carried_min_inliers", carried_min_inliers)
        .add("relocalisation_candidates", relocalisation_candidates)
        .add("relocalisation_sweep", relocalisation_sweep)
        .add("reanchor_after_s", reanchor_after_s)
        .add("reanchor_min_points", reanchor_min_points)
        .add("fallback_weight", fallback_weight)
        .add("fallback_max_jump", fallback_max_jump)
        .add("fallback_max_jump_deg", fallback_max_jump_deg)
        .add("optimisation_rounds", optimisation_rounds)
        .add("optimisation_iterations", optimisation_iterations);
    return f;
}

void TrackerParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                           const std::string& section)
{
    const char* s = "tracking";
    fields(section).load(cfg);

    requirePositive(virtual_baseline, s, "virtual_baseline");
    requirePositive(close_depth, s, "close_depth");
    if (keyframe_new_points < 0)
        throw core::InputError(
            mrpt::format("[tracking] keyframe_new_points = %d must be >= 0", keyframe_new_points));
    requirePositive(min_depth, s, "min_depth");
    if (!(max_depth > min_depth))
        throw core::InputError(mrpt::format("[tracking] max_depth = %g must be > min_depth = %g",
                                            max_depth, min_depth));
    requirePositive(motion_search_radius, s, "motion_search_radius");
    requirePositive(local_search_radius, s, "local_search_radius");
    requirePositive(init_min_points, s, "init_min_points");
    requirePositive(min_inliers, s, "min_inliers");
    requirePositive(keyframe_max_interval_s, s, "keyframe_max_interval_s");
    if (!(keyframe_min_interval_s >= 0.0))
        throw core::InputError(mrpt::format("[tracking] keyframe_min_interval_s = %g must be >= 0",
                                            keyframe_min_interval_s));
    if (!(keyframe_ref_ratio > 0.0 && keyframe_ref_ratio <= 1.0))
        throw core::InputError(mrpt::format("[tracking] keyframe_ref_ratio = %g must be in (0, 1]",
                                            keyframe_ref_ratio));
    if (revisit_radius < 0.0)
        throw core::InputError(
            mrpt::format("[tracking] revisit_radius = %g must be >= 0", revisit_radius));
    if (!(revisit_max_age_s >= 0.0) && revisit_max_age_s != -1.0)
        throw core::InputError(mrpt::format(
            "[tracking] revisit_max_age_s = %g must be >= 0, or -1 (follow loop closing)",
            revisit_max_age_s));
    requirePositive(relocalisation_candidates, s, "relocalisation_candidates");
    requirePositive(carried_min_inliers, s, "carried_min_inliers");
    if (relocalisation_sweep < 0)
        throw core::InputError(mrpt::format("[tracking] relocalisation_sweep = %d must be >= 0",
                                            relocalisation_sweep));
    if (!(carried_search_s >= 0.0))
        throw core::InputError(
            mrpt::format("[tracking] carried_search_s = %g must be >= 0", carried_search_s));
    if (!(reanchor_after_s >= 0.0))
        throw core::InputError(
            mrpt::format("[tracking] reanchor_after_s = %g must be >= 0", reanchor_after_s));
    requirePositive(reanchor_min_points, s, "reanchor_min_points");
    if (!(fallback_weight >= 0.0 && fallback_weight <= 1.0))
        throw core::InputError(
            mrpt::format("[tracking] fallback_weight = %g must be in [0, 1]", fallback_weight));
    if (!(fallback_max_jump >= 0.0) || !(fallback_max_jump_deg >= 0.0))
        throw core::InputError(mrpt::format(
            "[tracking] fallback_max_jump = %g and fallback_max_jump_deg = %g must be >= 0",
            fallback_max_jump, fallback_max_jump_deg));
    requirePositive(optimisation_rounds, s, "optimisation_rounds");
    requirePositive(optimisation_iterations, s, "optimisation_iterations");
}

void TrackerParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                         const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<TrackerParameters*>(this)->fields(section).save(cfg);
}

core::OptionFields LocalMappingParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "local_mapping");
    f.add("threaded", threaded)
        .add("ba_max_keyframes", ba_max_keyframes)
        .add("ba_iterations", ba_iterations)
        .add("ba_refine_iterations", ba_refine_iterations)
        .add("ba_min_shared_observations", ba_min_shared_observations)
        .add("global_ba_iterations", global_ba_iterations)
        .add("covisibility_min_weight", covisibility_min_weight)
        .add("fuse_neighbours", fuse_neighbours)
        .add("new_point_neighbours", new_point_neighbours)
        .add("keyframe_redundancy", keyframe_redundancy);
    return f;
}

void LocalMappingParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                const std::string& section)
{
    const char* s = "local_mapping";
    fields(section).load(cfg);
    if (ba_iterations < 0 || ba_refine_iterations < 0)
        throw core::InputError(mrpt::format(
            "[local_mapping] ba_iterations = %d and ba_refine_iterations = %d must be >= 0",
            ba_iterations, ba_refine_iterations));
    if (global_ba_iterations < 0)
        throw core::InputError(mrpt::format(
            "[local_mapping] global_ba_iterations = %d must be >= 0", global_ba_iterations));
    if (ba_min_shared_observations < 0)
        throw core::InputError(
            mrpt::format("[local_mapping] ba_min_shared_observations = %d must be >= 0",
                         ba_min_shared_observations));
    if (ba_max_keyframes < 2)
        throw core::InputError(
            mrpt::format("[local_mapping] ba_max_keyframes = %d must be >= 2", ba_max_keyframes));
    requirePositive(covisibility_min_weight, s, "covisibility_min_weight");
    if (fuse_neighbours < 0)
        throw core::InputError(
            mrpt::format("[local_mapping] fuse_neighbours = %d must be >= 0", fuse_neighbours));
    if (new_point_neighbours < 0)
        throw core::InputError(mrpt::format(
            "[local_mapping] new_point_neighbours = %d must be >= 0", new_point_neighbours));
    if (!(keyframe_redundancy > 0.0 && keyframe_redundancy <= 1.0))
        throw core::InputError(mrpt::format(
            "[local_mapping] keyframe_redundancy = %g must be in (0, 1]", keyframe_redundancy));
}

void LocalMappingParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                              const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<LocalMappingParameters*>(this)->fields(section).save(cfg);
}

core::OptionFields LoopClosingParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "loop_closing");
    f.add("enabled", enabled)
        .add("threaded", threaded)
        .add("min_keyframes", min_keyframes)
        .add("min_age_s", min_age_s)
        .add("min_matches", min_matches)
        .add("neighbour_score_ratio", neighbour_score_ratio)
        .add("max_candidates", max_candidates)
        .add("min_inliers", min_inliers)
        .add("inlier_distance", inlier_distance)
        .add("min_projected_matches", min_projected_matches)
        .add("min_correction_m", min_correction_m)
        .add("min_correction_deg", min_correction_deg)
        .add("pose_graph_iterations", pose_graph_iterations)
        .add("global_ba_iterations", global_ba_iterations);
    return f;
}

void LoopClosingParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section)
{
    const char* s = "loop_closing";
    fields(section).load(cfg);
    requirePositive(min_keyframes, s, "min_keyframes");
    requirePositive(min_matches, s, "min_matches");
    requirePositive(max_candidates, s, "max_candidates");
    requirePositive(inlier_distance, s, "inlier_distance");
    requirePositive(pose_graph_iterations, s, "pose_graph_iterations");
    if (min_inliers < 3)
        throw core::InputError(
            mrpt::format("[loop_closing] min_inliers = %d must be >= 3", min_inliers));
    if (!(neighbour_score_ratio >= 0.0 && neighbour_score_ratio <= 1.0))
        throw core::InputError(mrpt::format(
            "[loop_closing] neighbour_score_ratio = %g must be in [0, 1]", neighbour_score_ratio));
    if (min_correction_m < 0.0 || min_correction_deg < 0.0)
        throw core::InputError(mrpt::format(
            "[loop_closing] min_correction_m = %g and min_correction_deg = %g must be >= 0",
            min_correction_m, min_correction_deg));
    if (!(min_age_s >= 0.0) || min_projected_matches < 0 || global_ba_iterations < 0)
        throw core::InputError(
            mrpt::format("[loop_closing] min_age_s = %g, min_projected_matches = %d and "
                         "global_ba_iterations = %d must be >= 0",
                         min_age_s, min_projected_matches, global_ba_iterations));
}

void LoopClosingParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                             const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<LoopClosingParameters*>(this)->fields(section).save(cfg);
}
}  // namespace smap::slam
