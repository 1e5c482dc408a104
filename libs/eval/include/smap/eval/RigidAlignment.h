// Closed-form least-squares alignment of two corresponding point sets (Horn / Umeyama).
#pragma once

#include <Eigen/Core>

namespace smap::eval
{
struct Alignment
{
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    double scale = 1.0;

    Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
};

/// Finds R (proper rotation, det = +1), t and, when `withScale`, s minimising
/// sum_i |data_i - (s R model_i + t)|^2 (Umeyama 1991; without scale this is Horn's SE(3)
/// solution used by TUM's evaluate_ate.py). Columns are points; needs at least 3 points that are
/// not all collinear for a unique rotation (otherwise one minimiser is returned).
Alignment alignPoints(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data, bool withScale);
}  // namespace smap::eval
