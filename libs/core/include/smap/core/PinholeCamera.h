// Pinhole intrinsics (+ OpenCV plumb-bob distortion) of the image an RgbdFrame is expressed in.
//
// Optical frame convention used everywhere in semantic-mapper: x right, y down, z forward
// (the camera looks along +Z). Pixel (u, v) = (column, row); the centre of the top-left pixel
// is (0, 0), so a point on the optical axis projects to (cx, cy).
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/img/TCamera.h>

#include <Eigen/Core>
#include <array>
#include <opencv2/core/mat.hpp>
#include <string>

namespace smap::core
{
struct PinholeCamera
{
    int width = 0;
    int height = 0;
    double fx = 0.0;
    double fy = 0.0;
    double cx = 0.0;
    double cy = 0.0;
    /// k1, k2, p1, p2, k3 in OpenCV order; all zero when the image is undistorted.
    std::array<double, 5> distortion{};

    bool isValid() const { return width > 0 && height > 0 && fx > 0.0 && fy > 0.0; }
    bool hasDistortion() const;

    /// Undistorted pinhole back-projection of pixel (u, v) at depth z (metres).
    Eigen::Vector3d unproject(double u, double v, double z) const
    {
        return {(u - cx) * z / fx, (v - cy) * z / fy, z};
    }
    /// Undistorted pinhole projection of a point in the optical frame (z > 0).
    Eigen::Vector2d project(const Eigen::Vector3d& p_cam) const
    {
        return {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
    }

    /// Applies the plumb-bob distortion to normalised coordinates (x/z, y/z), in place, in
    /// the precision of T (the coefficients are cast to it first).
    template <class T>
    void distortNormalised(T& x, T& y) const
    {
        const auto k1 = static_cast<T>(distortion[0]), k2 = static_cast<T>(distortion[1]);
        const auto p1 = static_cast<T>(distortion[2]), p2 = static_cast<T>(distortion[3]);
        const auto k3 = static_cast<T>(distortion[4]);
        const T r2 = x * x + y * y;
        const T radial = T(1) + r2 * (k1 + r2 * (k2 + r2 * k3));
        const T xd = x * radial + T(2) * p1 * x * y + p2 * (r2 + T(2) * x * x);
        const T yd = y * radial + p1 * (r2 + T(2) * y * y) + T(2) * p2 * x * y;
        x = xd;
        y = yd;
    }

    cv::Mat cameraMatrix() const;  ///< 3x3 CV_64F
    cv::Mat distCoeffs() const;    ///< 1x5 CV_64F

    static PinholeCamera fromMrpt(const mrpt::img::TCamera& cam);
    mrpt::img::TCamera toMrpt() const;

    bool operator==(const PinholeCamera& o) const;
    bool operator!=(const PinholeCamera& o) const { return !(*this == o); }
    std::string toString() const;
};

/// Reads keys width, height, fx, fy, cx, cy (all required) and k1, k2, p1, p2, k3 (default 0)
/// from `section`. Throws InputError naming the section and the missing or invalid key.
PinholeCamera loadCamera(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
/// True when `section` holds at least one camera key (a partial override is an error).
bool hasCameraSection(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
void saveCamera(const PinholeCamera& cam, mrpt::config::CConfigFileBase& cfg,
                const std::string& section);

}  // namespace smap::core
