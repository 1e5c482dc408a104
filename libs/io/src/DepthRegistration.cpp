#include "smap/io/DepthRegistration.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <opencv2/calib3d.hpp>

namespace smap::io
{
std::vector<cv::Point2f> undistortedPixelRays(const core::PinholeCamera& camera)
{
    std::vector<cv::Point2f> pixels;
    pixels.reserve(static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height));
    for (int v = 0; v < camera.height; v++)
    {
        for (int u = 0; u < camera.width; u++)
            pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
    }
    std::vector<cv::Point2f> rays;
    if (camera.hasDistortion())
    {
        cv::undistortPoints(pixels, rays, camera.cameraMatrix(), camera.distCoeffs());
    }
    else
    {
        rays.resize(pixels.size());
        for (size_t i = 0; i < pixels.size(); i++)
        {
            rays[i] = {static_cast<float>((pixels[i].x - camera.cx) / camera.fx),
                       static_cast<float>((pixels[i].y - camera.cy) / camera.fy)};
        }
    }
    return rays;
}

DepthRegistration::DepthRegistration(const core::PinholeCamera& depthCamera,
                                     const core::PinholeCamera& colourCamera,
                                     const Eigen::Isometry3d& T_colour_depth)
    : depthCamera_(depthCamera),
      colourCamera_(colourCamera),
      T_colour_depth_(T_colour_depth),
      rays_(undistortedPixelRays(depthCamera)),
      colourDistorted_(colourCamera.hasDistortion()),
      fx_(static_cast<float>(colourCamera.fx)),
      fy_(static_cast<float>(colourCamera.fy)),
      cx_(static_cast<float>(colourCamera.cx)),
      cy_(static_cast<float>(colourCamera.cy)),
      width_(static_cast<float>(colourCamera.width)),
      height_(static_cast<float>(colourCamera.height))
{
    const Eigen::Matrix3d R = T_colour_depth_.linear();
    for (auto& component : rotatedRays_)
        component.resize(rays_.size());
    for (size_t i = 0; i < rays_.size(); i++)
    {
        const Eigen::Vector3d r = R * Eigen::Vector3d(rays_[i].x, rays_[i].y, 1.0);
        for (size_t k = 0; k < 3; k++)
            rotatedRays_[k][i] = static_cast<float>(r[static_cast<Eigen::Index>(k)]);
    }
}

namespace
{
struct RowProjection
{
    float fx, fy, cx, cy;  ///< cx, cy + 0.5: rounding to the nearest pixel is a truncation
    float tx, ty, tz;
};

/// Colour column + 0.5, row + 0.5 and depth of each depth pixel of a row (pinhole). No test
/// inside, so that the compiler vectorises the loop (with __restrict: the buffers do not
/// overlap, which it cannot prove by itself); the caller leaves out invalid depth and points
/// behind the colour camera, where this may divide by 0.
void projectPinholeRow(const float* __restrict depth, const float* __restrict rx,
                       const float* __restrict ry, const float* __restrict rz, size_t cols,
                       const RowProjection& p, float* __restrict us, float* __restrict vs,
                       float* __restrict zs)
{
    for (size_t u = 0; u < cols; u++)
    {
        const float z = depth[u];
        const float pz = z * rz[u] + p.tz;
        zs[u] = pz;
        const float inverseZ = 1.0F / pz;
        us[u] = p.fx * ((z * rx[u] + p.tx) * inverseZ) + p.cx;
        vs[u] = p.fy * ((z * ry[u] + p.ty) * inverseZ) + p.cy;
    }
}
}  // namespace

cv::Mat DepthRegistration::registerDepth(const cv::Mat& depth) const
{
    CV_Assert(depth.type() == CV_32FC1);
    CV_Assert(depth.cols == depthCamera_.width && depth.rows == depthCamera_.height);
    cv::Mat out = cv::Mat::zeros(colourCamera_.height, colourCamera_.width, CV_32FC1);
    auto* dst = out.ptr<float>();
    const size_t cols = static_cast<size_t>(depth.cols);
    // Per row, first where each pixel lands (a branch-free loop the compiler vectorises), then
    // the scatter into the colour image.
    std::vector<float> us(cols), vs(cols), zs(cols);
    for (int v = 0; v < depth.rows; v++)
    {
        const float* row = depth.ptr<float>(v);
        projectRow(row, cols * static_cast<size_t>(v), cols, us.data(), vs.data(), zs.data());
        scatterRow(row, us.data(), vs.data(), zs.data(), cols, dst);
    }
    return out;
}

void DepthRegistration::projectRow(const float* depth, size_t first, size_t cols, float* us,
                                   float* vs, float* zs) const
{
    const Eigen::Vector3f t = T_colour_depth_.translation().cast<float>();
    const float fx = fx_, fy = fy_, cx = cx_ + 0.5F, cy = cy_ + 0.5F;
    const RowProjection projection{fx, fy, cx, cy, t.x(), t.y(), t.z()};
    projectPinholeRow(depth, rotatedRays_[0].data() + first, rotatedRays_[1].data() + first,
                      rotatedRays_[2].data() + first, cols, projection, us, vs, zs);
    if (!colourDistorted_)
        return;
    for (size_t u = 0; u < cols; u++)  // redo with the colour camera's distortion
    {
        float x = (us[u] - cx) / fx, y = (vs[u] - cy) / fy;
        colourCamera_.distortNormalised(x, y);
        us[u] = fx * x + cx;
        vs[u] = fy * y + cy;
    }
}

void DepthRegistration::scatterRow(const float* depth, const float* us, const float* vs,
                                   const float* zs, size_t cols, float* dst) const
{
    const float width = width_, height = height_;
    const auto stride = static_cast<ptrdiff_t>(colourCamera_.width);
    for (size_t u = 0; u < cols; u++)
    {
        const float uf = us[u], vf = vs[u], z = zs[u];
        if (!(depth[u] > 0.0F && z > 0.0F && uf >= 0.0F && vf >= 0.0F && uf < width && vf < height))
            continue;
        float& d = dst[static_cast<ptrdiff_t>(vf) * stride + static_cast<ptrdiff_t>(uf)];
        // The nearest surface wins, without a branch on pixels still empty (0): positive
        // floats order as their bit patterns do, and minus one (unsigned) turns an empty
        // pixel's 0 into the largest value.
        uint32_t current = 0, candidate = 0;
        std::memcpy(&current, &d, sizeof d);
        std::memcpy(&candidate, &z, sizeof z);
        const uint32_t nearest = std::min(current - 1U, candidate - 1U) + 1U;
        std::memcpy(&d, &nearest, sizeof d);
    }
}
}  // namespace smap::io
