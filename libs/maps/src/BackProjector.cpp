#include "smap/maps/BackProjector.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

namespace smap::maps
{
core::OptionFields BackProjectionParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "backprojection");
    f.add("min_depth", min_depth).add("max_depth", max_depth).add("stride", stride);
    return f;
}

void BackProjectionParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                  const std::string& section)
{
    fields(section).load(cfg);
    if (!(min_depth >= 0.0 && max_depth > min_depth))
        throw core::InputError(mrpt::format(
            "[backprojection] need 0 <= min_depth (%g) < max_depth (%g)", min_depth, max_depth));
    if (stride < 1 || stride > 64)
        throw core::InputError(
            mrpt::format("[backprojection] stride = %d must be in [1, 64]", stride));
}

void BackProjectionParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                                const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<BackProjectionParameters*>(this)->fields(section).save(cfg);
}

BackProjector::BackProjector(const BackProjectionParameters& params) : params_(params) {}

const cv::Mat& BackProjector::rays(const core::PinholeCamera& camera)
{
    if (!rays_.empty() && camera == raysCamera_)
        return rays_;
    raysCamera_ = camera;
    cv::Mat pixels(camera.height * camera.width, 1, CV_32FC2);
    for (int v = 0; v < camera.height; v++)
        for (int u = 0; u < camera.width; u++)
            pixels.at<cv::Vec2f>(v * camera.width + u) = {static_cast<float>(u),
                                                          static_cast<float>(v)};
    cv::Mat normalised;
    if (camera.hasDistortion())
    {
        cv::undistortPoints(pixels, normalised, camera.cameraMatrix(), camera.distCoeffs());
    }
    else
    {
        normalised.create(pixels.size(), CV_32FC2);
        for (int i = 0; i < pixels.rows; i++)
        {
            const auto& p = pixels.at<cv::Vec2f>(i);
            normalised.at<cv::Vec2f>(i) = {static_cast<float>((p[0] - camera.cx) / camera.fx),
                                           static_cast<float>((p[1] - camera.cy) / camera.fy)};
        }
    }
    rays_ = normalised.reshape(2, camera.height);
    return rays_;
}

std::vector<SemanticPoint> BackProjector::project(const Images& images,
                                                  const core::PinholeCamera& camera,
                                                  const mrpt::poses::CPose3D& T_world_cam)
{
    const cv::Size size = images.depth.size();
    CV_Assert(images.depth.type() == CV_32FC1 && images.colour.type() == CV_8UC3 &&
              images.colour.size() == size && images.labels.type() == CV_8UC1 &&
              images.labels.size() == size &&
              (images.confidence.empty() ||
               (images.confidence.type() == CV_32FC1 && images.confidence.size() == size)) &&
              (images.dynamicMask.empty() ||
               (images.dynamicMask.type() == CV_8UC1 && images.dynamicMask.size() == size)));
    const cv::Mat& ray = rays(camera);
    CV_Assert(ray.size() == size);
    const Eigen::Matrix3d R = T_world_cam.getRotationMatrix().asEigen();
    const Eigen::Vector3d t(T_world_cam.x(), T_world_cam.y(), T_world_cam.z());
    const int stride = params_.stride;
    std::vector<SemanticPoint> out;
    out.reserve(static_cast<size_t>(size.area() / (stride * stride)));
    for (int v = 0; v < size.height; v += stride)
    {
        const float* d = images.depth.ptr<float>(v);
        const auto* c = images.colour.ptr<cv::Vec3b>(v);
        const auto* l = images.labels.ptr<uint8_t>(v);
        const float* conf = images.confidence.empty() ? nullptr : images.confidence.ptr<float>(v);
        const auto* m = images.dynamicMask.empty() ? nullptr : images.dynamicMask.ptr<uint8_t>(v);
        const auto* rv = ray.ptr<cv::Vec2f>(v);
        for (int u = 0; u < size.width; u += stride)
        {
            const double z = d[u];
            if ((m && m[u]) || !(z > 0.0) || z < params_.min_depth || z > params_.max_depth)
                continue;
            const Eigen::Vector3d X_cam(rv[u][0] * z, rv[u][1] * z, z);
            SemanticPoint p;
            p.position = (R * X_cam + t).cast<float>();
            p.b = c[u][0];
            p.g = c[u][1];
            p.r = c[u][2];
            p.label = l[u];
            p.confidence = conf ? conf[u] : 1.0f;
            p.u = u;
            p.v = v;
            out.push_back(p);
        }
    }
    return out;
}
}  // namespace smap::maps
