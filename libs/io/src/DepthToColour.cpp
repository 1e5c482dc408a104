#include "smap/io/DepthToColour.h"

#include <cmath>

#include "smap/io/DepthRegistration.h"

namespace smap::io
{
struct DepthToColour::Cache
{
    core::PinholeCamera depthCamera, colourCamera;
    Eigen::Isometry3d T_colour_depth;
    DepthRegistration registration;
};

DepthToColour::DepthToColour() = default;
DepthToColour::~DepthToColour() = default;
DepthToColour::DepthToColour(DepthToColour&&) noexcept = default;
DepthToColour& DepthToColour::operator=(DepthToColour&&) noexcept = default;

bool sameIntrinsics(const core::PinholeCamera& a, const core::PinholeCamera& b)
{
    const double tol = 1e-9;
    bool same = a.width == b.width && a.height == b.height && std::abs(a.fx - b.fx) < tol &&
                std::abs(a.fy - b.fy) < tol && std::abs(a.cx - b.cx) < tol &&
                std::abs(a.cy - b.cy) < tol;
    for (size_t i = 0; i < a.distortion.size(); i++)
        same = same && std::abs(a.distortion[i] - b.distortion[i]) < tol;
    return same;
}

bool isIdentity(const Eigen::Isometry3d& T)
{
    return (T.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 1e-6;
}

cv::Mat DepthToColour::onColourGrid(const cv::Mat& depth, const core::PinholeCamera& depthCamera,
                                    const core::PinholeCamera& colourCamera,
                                    const Eigen::Isometry3d& T_colour_depth)
{
    if (sameIntrinsics(depthCamera, colourCamera) && isIdentity(T_colour_depth))
        return depth;
    if (!cache_ || !sameIntrinsics(cache_->depthCamera, depthCamera) ||
        !sameIntrinsics(cache_->colourCamera, colourCamera) ||
        (cache_->T_colour_depth.matrix() - T_colour_depth.matrix()).cwiseAbs().maxCoeff() > 1e-12)
    {
        cache_ = std::make_unique<Cache>(
            Cache{depthCamera, colourCamera, T_colour_depth,
                  DepthRegistration(depthCamera, colourCamera, T_colour_depth)});
    }
    return cache_->registration.registerDepth(depth);
}
}  // namespace smap::io
