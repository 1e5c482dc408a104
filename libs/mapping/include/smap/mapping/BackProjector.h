// Back-projection of a keyframe's static pixels into the world (METHOD.md eq. 5): pixel (u, v)
// with depth z -> X_cam = ((u - cx) z / fx, (v - cy) z / fy, z) (distortion undone first when
// the camera has any), X_world = T_world_cam X_cam, with colour, label and class probability.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/core/RgbdFrame.h"
#include "smap/segmentation/SegmentationResult.h"

namespace smap::mapping
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

    /// The static pixels (dynamicMask == 0; an empty mask: every pixel) of `frame` with valid
    /// depth in [min_depth, max_depth], every stride-th, in the world frame. `segmentation`
    /// must be at the frame's resolution; its labels and probabilities are carried.
    std::vector<SemanticPoint> project(const core::RgbdFrame& frame,
                                       const segmentation::SegmentationResult& segmentation,
                                       const cv::Mat& dynamicMask,
                                       const mrpt::poses::CPose3D& T_world_cam);

    const BackProjectionParameters& parameters() const { return params_; }

private:
    /// Normalised undistorted ray (x/z, y/z) of every pixel, cached for one camera.
    const cv::Mat& rays(const core::PinholeCamera& camera);

    BackProjectionParameters params_;
    core::PinholeCamera raysCamera_;
    cv::Mat rays_;  ///< CV_32FC2
};
}  // namespace smap::mapping
