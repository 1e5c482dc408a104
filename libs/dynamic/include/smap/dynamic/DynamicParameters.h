// Options of the dynamic feature filter ([dynamic] section), loaded once from the
// configuration. The paper mode's values are the paper's (docs/method.md section 2).
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

#include "smap/core/OptionFields.h"

namespace smap::dynamic
{
enum class FilterMode
{
    Off,    ///< every keypoint is static
    Paper,  ///< the paper: five-point ego-motion, warp, LK residual flow > tau
    Strong  ///< beyond the paper: depth PnP ego-motion, adaptive tau, depth test, regions
};
std::string toString(FilterMode m);

struct DynamicParameters : public mrpt::config::CLoadableOptions
{
    FilterMode mode = FilterMode::Strong;
    /// Residual-flow tolerance (px): a keypoint moving more than this after ego-motion
    /// compensation is dynamic. Paper: 7.
    double tau = 7.0;
    int lk_window = 15;  ///< Lucas-Kanade window edge (px), paper mode
    int lk_levels = 2;   ///< Lucas-Kanade pyramid levels above the image, paper mode
    /// Five-point RANSAC: inlier threshold (px) and confidence.
    double essential_threshold = 1.0;
    double essential_confidence = 0.999;
    /// Ratio test for the frame-to-frame descriptor matches the ego-motion comes from.
    double match_ratio = 0.8;
    /// ... searched within this window (px) around the keypoint's position in the other frame.
    double match_radius = 80.0;

    // Strong mode only.
    /// Compare each frame with the newest earlier one at least this much older (s; at most the
    /// previous frame, as the paper, when its frames are that far apart): slow movers and
    /// people walking towards the camera move little between consecutive frames, and a wider
    /// gap multiplies their residual flow and depth change. 0.05 s: two frames back at 30
    /// frames/s, one at 15.
    double frame_gap_s = 0.05;
    /// Lucas-Kanade window (px) and pyramid levels of the strong mode: its flow starts at the
    /// ego-motion prediction, so static points need no search, and a small window mixes
    /// less of a nearby mover into background points.
    int strong_lk_window = 11;
    int strong_lk_levels = 1;
    double pnp_threshold = 2.0;  ///< PnP-RANSAC inlier threshold (px)
    /// The depth-PnP ego-motion matches at most this many current keypoints (spread evenly;
    /// 0 = all): a few hundred matches fix a 6-DoF pose, and matching is the costly part.
    int ego_max_queries = 250;
    /// Constant-velocity gate on the ego-motion: a RANSAC pose that differs from the previous
    /// frame's motion by more than this (m, degrees) is a hand-held camera's impossible jump
    /// in frame_gap_s, usually movers outvoting the background; the previous motion is
    /// kept instead (and refined by the flow), unless it has under a quarter of the RANSAC
    /// pose's support (then the prior was the wrong one). 0 = no gate.
    double ego_gate_translation = 0.03;
    double ego_gate_rotation_deg = 3.0;
    /// A RANSAC pose beyond the gate overrules the prior only with at least this many
    /// supporting matches: where people fill the view and the background's keypoints were
    /// flagged, a dozen walker matches must not decide the camera's motion. 0 = any support.
    int ego_gate_min_support = 30;
    /// Adaptive tau = clamp(median + tau_sigmas x 1.4826 MAD of the frame's residual flows,
    /// tau_min, tau).
    double tau_min = 2.0;
    double tau_sigmas = 6.0;
    /// Depth test: a keypoint measured closer than the warped previous surface by more than
    /// max(depth_margin, depth_ratio x z) is something that moved in front.
    double depth_margin = 0.10;
    double depth_ratio = 0.05;
    /// Occlusion: a keypoint whose reference pixel saw a surface more than this (m) closer
    /// was hidden in the reference frame (revealed background): no flow evidence.
    double occlusion_margin = 0.3;
    /// Region growing: a keypoint with at least region_min_neighbours neighbours within
    /// region_radius px and region_depth m in depth, most of them dynamic, is dynamic too.
    double region_radius = 40.0;
    double region_depth = 0.15;
    int region_min_neighbours = 3;
    /// Isolated flow evidence: a keypoint flagged by its flow alone, among at least
    /// region_min_neighbours depth-similar neighbours of which at most this fraction is
    /// dynamic, stays static (0 = off).
    double isolated_fraction = 0.34;
    /// Crowded frames: when more than this fraction of a frame's keypoints is dynamic, the
    /// next frame's ORB extraction takes corners where they were mostly dynamic only after
    /// every other region's (moverRegions()), so that people filling most of the view do not
    /// take most of the feature budget from the background. 1 = never, 0 = every frame.
    double extraction_priority_above = 0.5;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;

private:
    /// Every key of the section (default [dynamic]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
    void validateStrongMode() const;
    void validateFlowAndMatching() const;
};
}  // namespace smap::dynamic
