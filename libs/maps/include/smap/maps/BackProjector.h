// Back-projection of a keyframe's static pixels into the world (docs/method.md, eq. 5): pixel (u,
// v) with depth z -> X_cam = ((u - cx) z / fx, (v - cy) z / fy, z) (distortion undone first when
// the camera has any), X_world = T_world_cam X_cam, with colour, label and class probability.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/core/OptionFields.h"
#include "smap/core/PinholeCamera.h"

namespace smap::maps
{
/// [backprojection] section.
struct BackProjectionParameters : public mrpt::config::CLoadableOptions
{
    double min_depth = 0.3;  ///< m; nearer pixels are skipped (Kinect-like sensors)
    double max_depth = 4.0;  ///< m; farther pixels are too noisy for a map
    int stride = 1;          ///< use every stride-th pixel in u and v

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [backprojection]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};

struct SemanticPoint
{
    Eigen::Vector3f position;  ///< world frame, metres
    uint8_t r = 0, g = 0, b = 0;
    uint8_t label = 0;        ///< class id of the label set (255 = void)
    float confidence = 0.0f;  ///< probability of `label` at the pixel
    int u = 0, v = 0;         ///< source pixel
};

class BackProjector
{
public:
    explicit BackProjector(const BackProjectionParameters& params);

    /// One image of everything a pixel carries; all of one size, the camera's.
    struct Images
    {
        cv::Mat colour;       ///< CV_8UC3 BGR
        cv::Mat depth;        ///< CV_32FC1 metres, 0 = none
        cv::Mat labels;       ///< CV_8UC1 class ids (255 = void)
        cv::Mat confidence;   ///< CV_32FC1 probability of the label; empty: 1
        cv::Mat dynamicMask;  ///< CV_8UC1, non-zero = dynamic (skipped); empty: none
    };

    /// The static pixels with valid depth in [min_depth, max_depth], every stride-th, in the
    /// world frame, with colour, label and confidence.
    std::vector<SemanticPoint> project(const Images& images, const core::PinholeCamera& camera,
                                       const mrpt::poses::CPose3D& T_world_cam);

    const BackProjectionParameters& parameters() const { return params_; }

private:
    /// Normalised undistorted ray (x/z, y/z) of every pixel, cached for one camera.
    const cv::Mat& rays(const core::PinholeCamera& camera);

    BackProjectionParameters params_;
    core::PinholeCamera raysCamera_;
    cv::Mat rays_;  ///< CV_32FC2
};
}  // namespace smap::maps
