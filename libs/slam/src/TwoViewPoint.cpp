#include "TwoViewPoint.h"

#include <Eigen/SVD>
#include <cmath>

#include "smap/slam/KeyFrame.h"

namespace smap::slam
{
namespace
{
constexpr double kMinCosParallax = 0.9998;  // about 1.1 deg (ORB-SLAM)

/// Unit ray through keypoint `i` of `kf`, in world coordinates.
Eigen::Vector3d worldRay(const KeyFrame& kf, size_t i)
{
    const auto& p = kf.features.undistorted[i];
    const Eigen::Vector3d ray_cam = kf.camera.unproject(p.x, p.y, 1.0).normalized();
    return kf.T_cam_world().linear().transpose() * ray_cam;
}

/// The two rows keypoint `i` of `kf` adds to the linear (DLT) triangulation system.
void addDltRows(const KeyFrame& kf, size_t i, Eigen::Matrix4d& A, int row)
{
    const Eigen::Matrix<double, 3, 4> P = kf.T_cam_world().matrix().topRows<3>();
    const auto& p = kf.features.undistorted[i];
    const double x = (p.x - kf.camera.cx) / kf.camera.fx;
    const double y = (p.y - kf.camera.cy) / kf.camera.fy;
    A.row(row) = x * P.row(2) - P.row(0);
    A.row(row + 1) = y * P.row(2) - P.row(1);
}
}  // namespace

Eigen::Vector3d twoViewPosition(const KeyFrame& a, size_t i, const KeyFrame& b, size_t j,
                                const Eigen::Vector3d& p_depth)
{
    const double cosRays = worldRay(a, i).dot(worldRay(b, j));
    const double baseline = a.bf / a.camera.fx;
    const double cosStereo = std::cos(2.0 * std::atan2(0.5 * baseline, a.features.depth[i]));
    if (!(cosRays < cosStereo && cosRays < kMinCosParallax))
        return p_depth;
    Eigen::Matrix4d A;
    addDltRows(a, i, A, 0);
    addDltRows(b, j, A, 2);
    const Eigen::Vector4d X =
        Eigen::JacobiSVD<Eigen::Matrix4d>(A, Eigen::ComputeFullV).matrixV().col(3);
    if (std::abs(X.w()) < 1e-12)
        return p_depth;
    return X.head<3>() / X.w();
}
}  // namespace smap::slam
