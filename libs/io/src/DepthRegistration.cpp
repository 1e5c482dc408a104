#include "smap/io/DepthRegistration.h"

#include <cmath>
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
      rays_(undistortedPixelRays(depthCamera))
{
}

cv::Mat DepthRegistration::registerDepth(const cv::Mat& depth) const
{
    CV_Assert(depth.type() == CV_32FC1);
    CV_Assert(depth.cols == depthCamera_.width && depth.rows == depthCamera_.height);
    cv::Mat out = cv::Mat::zeros(colourCamera_.height, colourCamera_.width, CV_32FC1);
    const Eigen::Matrix3d R = T_colour_depth_.linear();
    const Eigen::Vector3d t = T_colour_depth_.translation();
    const auto& d = colourCamera_.distortion;
    const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4];
    for (int v = 0; v < depth.rows; v++)
    {
        const float* row = depth.ptr<float>(v);
        for (int u = 0; u < depth.cols; u++)
        {
            const float z = row[u];
            if (!(z > 0.0f))
                continue;
            const auto& ray = rays_[static_cast<size_t>(v) * depth.cols + u];
            const Eigen::Vector3d p = R * Eigen::Vector3d(ray.x * z, ray.y * z, z) + t;
            if (p.z() <= 0.0)
                continue;
            // Project with the colour camera's plumb-bob distortion.
            const double x = p.x() / p.z(), y = p.y() / p.z();
            const double r2 = x * x + y * y;
            const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
            const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
            const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
            const long uc = std::lround(colourCamera_.fx * xd + colourCamera_.cx);
            const long vc = std::lround(colourCamera_.fy * yd + colourCamera_.cy);
            if (uc < 0 || vc < 0 || uc >= out.cols || vc >= out.rows)
                continue;
            float& dst = out.at<float>(static_cast<int>(vc), static_cast<int>(uc));
            const auto zc = static_cast<float>(p.z());
            if (dst == 0.0f || zc < dst)
                dst = zc;
        }
    }
    return out;
}
}  // namespace smap::io
