// Ceres cost of one keypoint observation: pixel (u, v) and, with depth, the virtual right-image
// column uR = u - bf / z, weighted by the keypoint's level (1 / scale) and its feature weight.
// Pose blocks are angle-axis + translation of T_cam_world.
#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Geometry>

#include "Chi2.h"
#include "smap/core/PinholeCamera.h"

namespace smap::slam
{

struct Observation2D3
{
    double u = 0, v = 0, ur = -1;  ///< ur < 0: no depth (2 residuals)
    double sqrtInfo = 1;
    bool stereo() const { return ur >= 0; }
};

struct CameraModel
{
    double fx, fy, cx, cy, bf;
    explicit CameraModel(const core::PinholeCamera& c, double bf_)
        : fx(c.fx), fy(c.fy), cx(c.cx), cy(c.cy), bf(bf_)
    {
    }
};

template <int N>
struct ReprojectionResidual
{
    ReprojectionResidual(const Observation2D3& o, const CameraModel& c) : obs(o), cam(c) {}

    template <typename T>
    bool operator()(const T* pose, const T* point, T* r) const
    {
        T p[3];
        ceres::AngleAxisRotatePoint(pose, point, p);
        p[0] += pose[3];
        p[1] += pose[4];
        p[2] += pose[5];
        const T invZ = T(1) / p[2];
        const T u = T(cam.fx) * p[0] * invZ + T(cam.cx);
        const T v = T(cam.fy) * p[1] * invZ + T(cam.cy);
        r[0] = (u - T(obs.u)) * T(obs.sqrtInfo);
        r[1] = (v - T(obs.v)) * T(obs.sqrtInfo);
        if constexpr (N == 3)
            r[2] = (u - T(cam.bf) * invZ - T(obs.ur)) * T(obs.sqrtInfo);
        return true;
    }

    Observation2D3 obs;
    CameraModel cam;
};

/// Pose-only variant: the point is a constant.
template <int N>
struct PoseOnlyResidual
{
    PoseOnlyResidual(const Observation2D3& o, const CameraModel& c, const Eigen::Vector3d& p)
        : inner(o, c), point(p)
    {
    }
    template <typename T>
    bool operator()(const T* pose, T* r) const
    {
        const T pt[3] = {T(point.x()), T(point.y()), T(point.z())};
        return inner(pose, pt, r);
    }
    ReprojectionResidual<N> inner;
    Eigen::Vector3d point;
};

/// Squared, unrobust, information-weighted error and whether the point is in front.
inline double reprojectionChi2(const double* pose, const double* point, const Observation2D3& o,
                               const CameraModel& c, bool& in_front)
{
    double p[3];
    ceres::AngleAxisRotatePoint(pose, point, p);
    p[0] += pose[3];
    p[1] += pose[4];
    p[2] += pose[5];
    in_front = p[2] > 1e-6;
    if (!in_front)
        return 1e12;
    double r[3];
    if (o.stereo())
    {
        ReprojectionResidual<3>(o, c)(pose, point, r);
        return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    }
    ReprojectionResidual<2>(o, c)(pose, point, r);
    return r[0] * r[0] + r[1] * r[1];
}

inline void poseToParams(const Eigen::Isometry3d& T, double* pose)
{
    const Eigen::AngleAxisd aa(T.rotation());
    const Eigen::Vector3d w = aa.angle() * aa.axis();
    pose[0] = w.x();
    pose[1] = w.y();
    pose[2] = w.z();
    pose[3] = T.translation().x();
    pose[4] = T.translation().y();
    pose[5] = T.translation().z();
}

inline Eigen::Isometry3d paramsToPose(const double* pose)
{
    const Eigen::Vector3d w(pose[0], pose[1], pose[2]);
    const double angle = w.norm();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (angle > 1e-12)
        T.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
    T.translation() = Eigen::Vector3d(pose[3], pose[4], pose[5]);
    return T;
}
}  // namespace smap::slam
