// Kinect-like degradation of a perfect depth image.
#pragma once

#include <opencv2/core/mat.hpp>
#include <random>

#include "smap/core/PinholeCamera.h"

namespace smap::sim
{
struct DepthNoiseModel
{
    bool enabled = true;
    double minRange = 0.4;              ///< m; nearer returns are holes
    double maxRange = 8.0;              ///< m; farther returns are holes
    double baseline = 0.075;            ///< m; projector-camera baseline for disparity quantisation
    double subpixel = 1.0 / 8.0;        ///< disparity quantum, pixels
    double holeProbabilityEdges = 0.6;  ///< at depth discontinuities (silhouettes)
    double holeProbabilityDark = 0.7;   ///< on very dark surfaces (grey < 25)
    double grazingCosine = 0.17;        ///< surfaces seen at > ~80 deg from the ray: holes

    /// Axial noise sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 metres (Nguyen et al., 2012).
    static double sigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }

    /// Returns the degraded depth (0 = hole); `colour` gives the dark-surface holes.
    cv::Mat apply(const cv::Mat& depth, const cv::Mat& colour, const core::PinholeCamera& camera,
                  std::mt19937& rng) const;
};
}  // namespace smap::sim
