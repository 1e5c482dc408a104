// Options of the dynamic feature filter ([dynamic] section), loaded once from the
// configuration. The paper mode's values are the paper's (METHOD.md section 2).
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace smap::dynamic
{
enum class FilterMode
{
    Off,   ///< every keypoint is static
    Paper  ///< the paper: five-point ego-motion, warp, LK residual flow > tau
};
std::string toString(FilterMode m);

struct DynamicParameters : public mrpt::config::CLoadableOptions
{
    FilterMode mode = FilterMode::Off;
    /// Residual-flow tolerance (px): a keypoint moving more than this after ego-motion
    /// compensation is dynamic. Paper: 7.
    double tau = 7.0;
    int lk_window = 15;  ///< Lucas-Kanade window edge (px)
    int lk_levels = 2;   ///< Lucas-Kanade pyramid levels above the image
    /// Five-point RANSAC: inlier threshold (px) and confidence.
    double essential_threshold = 1.0;
    double essential_confidence = 0.999;
    /// Ratio test for the frame-to-frame descriptor matches the ego-motion comes from.
    double match_ratio = 0.8;
    /// ... searched within this window (px) around the keypoint's position in the other frame.
    double match_radius = 80.0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};
}  // namespace smap::dynamic
