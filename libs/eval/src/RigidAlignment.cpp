#include "smap/eval/RigidAlignment.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <stdexcept>

namespace smap::eval
{
Alignment alignPoints(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data, bool withScale)
{
    if (model.cols() != data.cols() || model.cols() == 0)
        throw std::invalid_argument("alignPoints: point sets must be non-empty and of equal size");
    const auto n = static_cast<double>(model.cols());
    const Eigen::Vector3d muModel = model.rowwise().mean();
    const Eigen::Vector3d muData = data.rowwise().mean();
    const Eigen::Matrix3Xd m = model.colwise() - muModel;
    const Eigen::Matrix3Xd d = data.colwise() - muData;

    // Cross-covariance; its SVD gives the rotation that best maps model onto data.
    const Eigen::Matrix3d sigma = d * m.transpose() / n;
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0)
        S(2, 2) = -1.0;

    Alignment a;
    a.R = svd.matrixU() * S * svd.matrixV().transpose();
    if (withScale)
    {
        const double varModel = m.squaredNorm() / n;
        a.scale = varModel > 0.0 ? (svd.singularValues().asDiagonal() * S).trace() / varModel : 1.0;
    }
    a.t = muData - a.scale * a.R * muModel;
    return a;
}
}  // namespace smap::eval
