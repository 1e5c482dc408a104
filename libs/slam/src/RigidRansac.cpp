#include "smap/slam/RigidRansac.h"

#include <Eigen/SVD>
#include <random>

namespace smap::slam
{
namespace
{
/// Least-squares rigid motion (Kabsch) of the pairs in `which`, each weighted by
/// 1 / tolerance^2 so that the far, noisy pairs pull less.
Eigen::Isometry3d fitRigid(const std::vector<Eigen::Vector3d>& a,
                           const std::vector<Eigen::Vector3d>& b,
                           const std::vector<double>& tolerance, const std::vector<size_t>& which)
{
    double wSum = 0.0;
    Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
    for (size_t k : which)
    {
        const double w = 1.0 / (tolerance[k] * tolerance[k]);
        ca += w * a[k];
        cb += w * b[k];
        wSum += w;
    }
    ca /= wSum;
    cb /= wSum;
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    for (size_t k : which)
        H += (1.0 / (tolerance[k] * tolerance[k])) * (b[k] - cb) * (a[k] - ca).transpose();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0)
        D(2, 2) = -1.0;  // a reflection is not a motion
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = svd.matrixV() * D * svd.matrixU().transpose();
    T.translation() = ca - T.linear() * cb;
    return T;
}

std::vector<size_t> inliersOf(const std::vector<Eigen::Vector3d>& a,
                              const std::vector<Eigen::Vector3d>& b, const Eigen::Isometry3d& T,
                              const std::vector<double>& tolerance)
{
    std::vector<size_t> in;
    for (size_t k = 0; k < a.size(); ++k)
        if ((a[k] - T * b[k]).squaredNorm() <= tolerance[k] * tolerance[k])
            in.push_back(k);
    return in;
}

/// Three samples whose points in b span a triangle (not nearly collinear).
bool wellSpread(const std::vector<Eigen::Vector3d>& b, const std::vector<size_t>& s)
{
    const Eigen::Vector3d u = b[s[1]] - b[s[0]], v = b[s[2]] - b[s[0]];
    return u.cross(v).norm() > 1e-4;
}
}  // namespace

std::optional<RigidEstimate> estimateRigidRansac(const std::vector<Eigen::Vector3d>& a,
                                                 const std::vector<Eigen::Vector3d>& b,
                                                 const std::vector<double>& tolerance,
                                                 int min_inliers, int iterations, uint32_t seed)
{
    if (a.size() != b.size() || a.size() != tolerance.size() || a.size() < 3)
        return std::nullopt;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<size_t> pick(0, a.size() - 1);
    std::vector<size_t> best;
    for (int it = 0; it < iterations; ++it)
    {
        std::vector<size_t> s = {pick(rng), pick(rng), pick(rng)};
        if (s[0] == s[1] || s[0] == s[2] || s[1] == s[2] || !wellSpread(b, s))
            continue;
        auto in = inliersOf(a, b, fitRigid(a, b, tolerance, s), tolerance);
        if (in.size() > best.size())
            best = std::move(in);
    }
    if (best.size() < 3 || static_cast<int>(best.size()) < min_inliers)
        return std::nullopt;
    // Least-squares refits on the inliers (the motion of all of them may take in a few more).
    RigidEstimate e;
    e.inliers = std::move(best);
    for (int round = 0; round < 2 && e.inliers.size() >= 3; ++round)
    {
        e.T_a_b = fitRigid(a, b, tolerance, e.inliers);
        e.inliers = inliersOf(a, b, e.T_a_b, tolerance);
    }
    if (static_cast<int>(e.inliers.size()) < min_inliers)
        return std::nullopt;
    return e;
}
}  // namespace smap::slam
