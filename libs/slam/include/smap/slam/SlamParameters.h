// Options of tracking ([tracking]), local mapping ([local_mapping]) and loop closing
// ([loop_closing]), loaded once from the
// configuration. Defaults are ORB-SLAM2's RGB-D values where it has one.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include "smap/core/OptionFields.h"

namespace smap::slam
{
struct TrackerParameters : public mrpt::config::CLoadableOptions
{
    /// Virtual stereo baseline (m) for the right-image coordinate u - fx * b / z.
    double virtual_baseline = 0.08;
    /// Keypoints closer than this (m) count as "close": their depth is trusted for new points.
    double close_depth = 3.0;
    /// A keyframe makes new map points from depth for every close keypoint and, nearest first,
    /// for farther ones until it has this many (ORB-SLAM: 100). Where most of the view is far
    /// (a corridor) more keep the map from thinning out (docs/results.md).
    int keyframe_new_points = 100;
    double min_depth = 0.1;  ///< keypoint depths outside [min_depth, max_depth] are ignored
    double max_depth = 8.0;
    /// Depth on a discontinuity (5x5 span > ratio x z) is not trusted; <= 0 disables.
    double depth_edge_ratio = 0.05;
    int init_min_points = 300;         ///< keypoints with depth needed to start the map
    double motion_search_radius = 15;  ///< px at level 0, motion-model projection search
    double local_search_radius = 3;    ///< px at level 0 (x view-angle factor), local map
    int min_matches_motion = 20;       ///< motion-model matches before optimisation
    int min_inliers = 30;              ///< inliers that keep tracking "ok"
    int min_inliers_after_relocalisation = 50;
    /// A keyframe at least this often (s of the recording's time; ORB-SLAM: its frame rate in
    /// frames, one second).
    double keyframe_max_interval_s = 1.0;
    /// While tracking is strong, no new keyframe within this time (s) of the last one (the
    /// deterministic stand-in for ORB-SLAM's "local mapping is busy"; 0: as soon as needed).
    /// keyframe_max_interval_s still forces one, and weak tracking still makes one at once.
    double keyframe_min_interval_s = 0.5;
    double keyframe_ref_ratio = 0.75;  ///< tracked / reference-keyframe points that asks for one
    /// Keyframes within this distance (m) of the camera, looking the same way, join the local
    /// map even without shared points (revisits); 0 disables.
    double revisit_radius = 0.5;
    /// Only keyframes made at most this long (s) before join as revisits; older places are
    /// left to loop closing, which corrects the drift before joining them. 0: any age; -1:
    /// [loop_closing] min_age_s when loop closing is on, else any age (RgbdSlam resolves it).
    double revisit_max_age_s = -1.0;
    /// A frame that no other stage tracks, and for this long (s) after a loss a lost frame
    /// before relocalisation, is searched in the local map from the pose the outside odometry
    /// carried it to (Frame::odometry_T_cam_earlier, chained over lost frames): the last
    /// fallback (TrackingFallback::CarriedPose), min_inliers to succeed (carried_min_inliers
    /// for a lost frame). 0 disables it.
    double carried_search_s = 1.0;
    /// Inliers a lost frame needs to be placed from the carried pose (a frame still tracking
    /// needs min_inliers): chained over several lost frames the odometry can be centimetres
    /// off, and the search then finds chance matches enough to settle on a wrong pose that the
    /// new keyframe's points would keep. As many as a relocalisation needs, by default.
    int carried_min_inliers = 50;
    int relocalisation_candidates = 5;  ///< keyframes tried per lost frame, by image similarity
    /// Keyframes tried per lost frame beyond those: the next ones down the similarity ranking,
    /// a further slice on each lost frame in a row (wrapping), so that an outage tries every
    /// keyframe in turn, however its thumbnail ranks. 0 disables.
    int relocalisation_sweep = 5;
    /// Lost for this long (s) without relocalisation placing a frame, the next frame
    /// with reanchor_min_points keypoints shown static with depth re-anchors: it starts a new
    /// part of the map (KeyFrame::part), as a keyframe at the pose predicted by the outside
    /// odometry (Frame::odometry_T_cam_earlier) or else by the last tracked frame's velocity
    /// (at most reanchor_after_s ahead), its depth gives new points, and tracking goes on
    /// from there (status "reanchored"). The camera has then usually moved where the map
    /// cannot place it. Every tracked frame of the new part is also relocalised among the
    /// other parts' keyframes; where one is placed, the newer part moves rigidly into the
    /// older one's frame and they become one (Map::mergePart). A part that never meets the
    /// rest again is dropped at the end with its frames' poses, unless it poses the most
    /// frames (RgbdSlam::finish). 0 = never (lost until relocalised, as ORB-SLAM2). The
    /// default waits a second: a part started at once begins amid what lost tracking (people
    /// filling the view) and tracks poorly (docs/tracking.md).
    double reanchor_after_s = 1.0;
    /// Keypoints shown static with depth that a frame needs to re-anchor (its points start the
    /// new part of the map).
    int reanchor_min_points = 100;
    /// A frame that fails to track with the outside weights (e.g. the dynamic filter's) is
    /// tried once more with every weight raised to at least this value: the map points are
    /// static, so keypoints the filter flagged by mistake can still match them. The weights
    /// are restored afterwards (no map points from excluded keypoints). 0 disables.
    double fallback_weight = 0.5;
    /// A pose that only a fallback stage (raised weights, still movable) found is kept only
    /// within this distance (m) of the constant-velocity prediction, scaled by the time since
    /// the last frame over the velocity's own interval: where movers fill the view those
    /// stages can lock onto them, and a hand-held camera does not jump centimetres away from
    /// its motion in one frame. The frame is lost instead. 0 disables.
    double fallback_max_jump = 0.04;
    /// As fallback_max_jump, for rotation (deg). 0 disables.
    double fallback_max_jump_deg = 2.0;
    int optimisation_rounds = 4;       ///< pose-only optimisation: outlier rejection rounds
    int optimisation_iterations = 10;  ///< Levenberg-Marquardt iterations per round

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [tracking]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};

struct LocalMappingParameters : public mrpt::config::CLoadableOptions
{
    /// Run local mapping in its own thread (tracking never waits for it). false: every
    /// keyframe is processed before the next frame is tracked, results are deterministic.
    bool threaded = false;
    int ba_max_keyframes = 14;     ///< the keyframe and its strongest covisible ones move
    int ba_iterations = 3;         ///< robust local BA before outliers are removed
    int ba_refine_iterations = 5;  ///< after removal
    /// A keyframe with fewer inlier observations of points that another keyframe of the
    /// adjustment sees too holds its pose in local and global BA (tracking placed it from at
    /// least `[tracking] min_inliers`; a few wrong points would carry it off). 0: none held.
    int ba_min_shared_observations = 20;
    /// At the end of a run, a bundle adjustment over every keyframe and point: this many robust
    /// iterations, then as many after outliers are removed (0 = none).
    int global_ba_iterations = 10;
    int covisibility_min_weight = 15;  ///< shared points that make a covisibility edge
    int fuse_neighbours = 10;          ///< covisible keyframes searched for duplicate points
    /// Covisible keyframes searched for a second view of a keypoint with depth but no map point
    /// (mostly beyond close_depth): one that agrees starts a point seen by both (0: none).
    int new_point_neighbours = 10;
    double keyframe_redundancy = 0.9;  ///< cull a keyframe whose points are this redundant

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [local_mapping]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};

struct LoopClosingParameters : public mrpt::config::CLoadableOptions
{
    /// Look for places seen before in every new keyframe and correct the drift when one is found.
    bool enabled = true;
    /// Detect and correct in its own thread (tracking never waits). false: right after local
    /// mapping processed the keyframe, on its thread, so that results are deterministic when
    /// local mapping is synchronous too.
    bool threaded = true;
    int min_keyframes = 10;  ///< keyframes in the map before detection starts
    /// Candidates: keyframes at least this much older (s) than the new one (covisible with
    /// it or not: tracking links a place it comes back to when the drift is small) ...
    double min_age_s = 10.0;
    /// ... whose indexed descriptors hold a copy (within 50 bits) of at least this many of the
    /// new keyframe's ...
    int min_matches = 40;
    /// ... and at least this share of the lowest score among its covisible keyframes.
    double neighbour_score_ratio = 0.75;
    int max_candidates = 3;  ///< best candidates verified per keyframe
    /// 3D-3D RANSAC between the keyframe's keypoints (depth) and the candidate's map points:
    /// inliers within `inlier_distance` (m) needed.
    int min_inliers = 20;
    double inlier_distance = 0.05;
    /// Then the candidate and its covisible keyframes' points projected with that pose: matches
    /// needed to accept the loop.
    int min_projected_matches = 80;
    /// A verified loop whose pose differs from the keyframe's by less than both of these is a
    /// consistent revisit: counted, nothing corrected.
    double min_correction_m = 0.02;
    double min_correction_deg = 0.5;
    int pose_graph_iterations = 20;
    /// Robust iterations of the global bundle adjustment after each correction (0: none).
    int global_ba_iterations = 5;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [loop_closing]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};
}  // namespace smap::slam
