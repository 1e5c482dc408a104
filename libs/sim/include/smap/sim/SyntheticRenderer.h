// Renders a SyntheticScene headless: the room with MRPT's CFBORender over EGL (colour, noise-free
// depth, and a flat-coloured copy for class labels and instance ids), then its people as sprite
// billboards over it (SpriteBillboard), with the mask of pixels moving at that instant.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <opencv2/core/mat.hpp>

#include "smap/core/PinholeCamera.h"
#include "smap/sim/SyntheticScene.h"

namespace smap::sim
{
struct RenderedFrame
{
    cv::Mat colour;     ///< CV_8UC3 BGR
    cv::Mat depth;      ///< CV_32FC1 metres along +Z, noise-free; 0 where nothing was hit
    cv::Mat labels;     ///< CV_8UC1 PASCAL VOC ids
    cv::Mat instances;  ///< CV_16UC1 instance ids (0 = none)
    cv::Mat dynamic;    ///< CV_8UC1, 255 on objects moving at this instant, else 0
};

class SyntheticRenderer
{
public:
    /// `camera` must be undistorted. Depth is rendered with clip distances [clipNear, clipFar].
    SyntheticRenderer(const SyntheticScene& scene, const core::PinholeCamera& camera,
                      double clipNear = 0.2, double clipFar = 12.0);
    ~SyntheticRenderer();
    SyntheticRenderer(const SyntheticRenderer&) = delete;
    SyntheticRenderer& operator=(const SyntheticRenderer&) = delete;

    /// Renders the world at time t seen from T_world_cam. A person's pixel counts as moving
    /// when its point on the person moved more than 1 mm between t - motionDt and t.
    RenderedFrame render(double t, const mrpt::poses::CPose3D& T_world_cam,
                         double motionDt = 1.0 / 30.0);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
}  // namespace smap::sim
