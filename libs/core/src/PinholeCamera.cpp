#include "smap/core/PinholeCamera.h"

#include <mrpt/core/format.h>

#include "smap/core/InputError.h"

namespace smap::core
{
namespace
{
constexpr std::array<const char*, 5> kDistortionKeys = {"k1", "k2", "p1", "p2", "k3"};
constexpr std::array<const char*, 6> kRequiredKeys = {"width", "height", "fx", "fy", "cx", "cy"};
}  // namespace

bool PinholeCamera::hasDistortion() const
{
    for (double d : distortion)
    {
        if (d != 0.0)
            return true;
    }
    return false;
}

cv::Mat PinholeCamera::cameraMatrix() const
{
    cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
    K.at<double>(0, 0) = fx;
    K.at<double>(1, 1) = fy;
    K.at<double>(0, 2) = cx;
    K.at<double>(1, 2) = cy;
    return K;
}

cv::Mat PinholeCamera::distCoeffs() const
{
    cv::Mat d(1, 5, CV_64F);
    for (int i = 0; i < 5; i++)
        d.at<double>(0, i) = distortion[i];
    return d;
}

PinholeCamera PinholeCamera::fromMrpt(const mrpt::img::TCamera& cam)
{
    PinholeCamera c;
    c.width = static_cast<int>(cam.ncols);
    c.height = static_cast<int>(cam.nrows);
    c.fx = cam.fx();
    c.fy = cam.fy();
    c.cx = cam.cx();
    c.cy = cam.cy();
    // TCamera::dist holds k1 k2 p1 p2 k3 (plumb_bob) first.
    for (size_t i = 0; i < 5; i++)
        c.distortion[i] = cam.dist[i];
    return c;
}

mrpt::img::TCamera PinholeCamera::toMrpt() const
{
    mrpt::img::TCamera cam;
    cam.ncols = static_cast<uint32_t>(width);
    cam.nrows = static_cast<uint32_t>(height);
    cam.setIntrinsicParamsFromValues(fx, fy, cx, cy);
    cam.dist.fill(0.0);
    for (size_t i = 0; i < 5; i++)
        cam.dist[i] = distortion[i];
    return cam;
}

bool PinholeCamera::operator==(const PinholeCamera& o) const
{
    return width == o.width && height == o.height && fx == o.fx && fy == o.fy && cx == o.cx &&
           cy == o.cy && distortion == o.distortion;
}

std::string PinholeCamera::toString() const
{
    return mrpt::format("%dx%d fx=%.4f fy=%.4f cx=%.4f cy=%.4f dist=[%g %g %g %g %g]", width,
                        height, fx, fy, cx, cy, distortion[0], distortion[1], distortion[2],
                        distortion[3], distortion[4]);
}

bool hasCameraSection(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    for (const char* k : kRequiredKeys)
    {
        if (cfg.keyExists(section, k))
            return true;
    }
    for (const char* k : kDistortionKeys)
    {
        if (cfg.keyExists(section, k))
            return true;
    }
    return false;
}

PinholeCamera loadCamera(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    for (const char* k : kRequiredKeys)
    {
        if (!cfg.keyExists(section, k))
        {
            throw InputError(mrpt::format(
                "camera section [%s] lacks required key '%s' (needs width, height, fx, fy, cx, "
                "cy; k1 k2 p1 p2 k3 optional)",
                section.c_str(), k));
        }
    }
    PinholeCamera c;
    c.width = cfg.read_int(section, "width", 0);
    c.height = cfg.read_int(section, "height", 0);
    c.fx = cfg.read_double(section, "fx", 0.0);
    c.fy = cfg.read_double(section, "fy", 0.0);
    c.cx = cfg.read_double(section, "cx", 0.0);
    c.cy = cfg.read_double(section, "cy", 0.0);
    for (size_t i = 0; i < kDistortionKeys.size(); i++)
        c.distortion[i] = cfg.read_double(section, kDistortionKeys[i], 0.0);
    if (!c.isValid())
    {
        throw InputError(
            mrpt::format("camera section [%s] is invalid: %s (width, height, fx, fy must be > 0)",
                         section.c_str(), c.toString().c_str()));
    }
    return c;
}

void saveCamera(const PinholeCamera& cam, mrpt::config::CConfigFileBase& cfg,
                const std::string& section)
{
    cfg.write(section, "width", cam.width);
    cfg.write(section, "height", cam.height);
    cfg.write(section, "fx", cam.fx);
    cfg.write(section, "fy", cam.fy);
    cfg.write(section, "cx", cam.cx);
    cfg.write(section, "cy", cam.cy);
    for (size_t i = 0; i < kDistortionKeys.size(); i++)
        cfg.write(section, kDistortionKeys[i], cam.distortion[i]);
}

}  // namespace smap::core
