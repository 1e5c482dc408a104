#include "smap/slam/PoseOptimizer.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "Chi2.h"
#include "smap/slam/Frame.h"
#include "smap/slam/MapPoint.h"

namespace smap::slam
{
namespace
{
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

/// A matched keypoint of the frame: its observation (pixel, and the virtual right column uR
/// when it has depth, else uR < 0), its information weight and its map point's position.
struct Edge
{
    size_t index;
    double u, v, ur;
    double sqrtInfo;
    Eigen::Vector3d point_world;
    bool stereo() const { return ur >= 0; }
    double chi2Bound() const { return stereo() ? kChi2Stereo : kChi2Mono; }
};

/// The pinhole intrinsics and the virtual stereo baseline times fx.
struct Intrinsics
{
    double fx, fy, cx, cy, bf;
};

/// The usable matched keypoints (their outlier flags cleared).
std::vector<Edge> collectEdges(Frame& frame)
{
    std::vector<Edge> edges;
    const auto& fs = frame.features;
    for (size_t i = 0; i < frame.size(); ++i)
    {
        const auto& mp = frame.points[i];
        if (!mp || !frame.usable(i))
            continue;
        const double invSigma2 = fs.pyramid.invSigma2[static_cast<size_t>(fs.keypoints[i].octave)];
        edges.push_back({i, fs.undistorted[i].x, fs.undistorted[i].y,
                         fs.hasDepth(i) ? static_cast<double>(fs.rightU[i]) : -1.0,
                         std::sqrt(invSigma2 * frame.weights[i]), mp->position_world});
        frame.outlier[i] = false;
    }
    return edges;
}

/// The weighted residual of one edge at T_cam_world (2 or 3 rows used) and, when `jacobian`
/// is given, its derivative with respect to a left perturbation [w, v] of the pose
/// (T <- [exp(w), v] * T). False when the point is not in front of the camera.
bool edgeResidual(const Edge& e, const Intrinsics& k, const Eigen::Isometry3d& T_cam_world,
                  Eigen::Vector3d& r, Eigen::Matrix<double, 3, 6>* jacobian)
{
    const Eigen::Vector3d p = T_cam_world * e.point_world;
    if (p.z() <= 1e-6)
        return false;
    const double invZ = 1.0 / p.z();
    const double u = k.fx * p.x() * invZ + k.cx;
    const double v = k.fy * p.y() * invZ + k.cy;
    r.x() = (u - e.u) * e.sqrtInfo;
    r.y() = (v - e.v) * e.sqrtInfo;
    r.z() = e.stereo() ? (u - k.bf * invZ - e.ur) * e.sqrtInfo : 0.0;
    if (jacobian == nullptr)
        return true;
    // d(u, v, uR)/dp, then dp/d[w, v] = [-[p]x, I].
    Eigen::Matrix3d dproj;
    dproj << k.fx * invZ, 0, -k.fx * p.x() * invZ * invZ,  //
        0, k.fy * invZ, -k.fy * p.y() * invZ * invZ,       //
        k.fx * invZ, 0, (-k.fx * p.x() + k.bf) * invZ * invZ;
    if (!e.stereo())
        dproj.row(2).setZero();
    Eigen::Matrix3d skew;
    skew << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
    jacobian->leftCols<3>() = -dproj * skew;
    jacobian->rightCols<3>() = dproj;
    *jacobian *= e.sqrtInfo;
    return true;
}

/// Huber's cost of a squared error and the weight its residual gets in the normal equations
/// (iteratively reweighted least squares); plain least squares when not `robust`.
double robustCost(double squared, double bound, bool robust, double& weight)
{
    weight = 1.0;
    if (!robust || squared <= bound)
        return squared;
    const double delta = std::sqrt(bound);
    const double norm = std::sqrt(squared);
    weight = delta / norm;
    return 2.0 * delta * norm - bound;
}

/// The total cost over the inlier edges at T_cam_world; with H and b, also the Gauss-Newton
/// normal equations H dx = -b.
double linearise(const std::vector<Edge>& edges, const std::vector<bool>& outlier,
                 const Intrinsics& k, const Eigen::Isometry3d& T_cam_world, bool robust, Matrix6* H,
                 Vector6* b)
{
    if (H != nullptr)
    {
        H->setZero();
        b->setZero();
    }
    double cost = 0;
    Eigen::Vector3d r;
    Eigen::Matrix<double, 3, 6> J;
    for (size_t i = 0; i < edges.size(); ++i)
    {
        if (outlier[i])
            continue;
        const Edge& e = edges[i];
        if (!edgeResidual(e, k, T_cam_world, r, H != nullptr ? &J : nullptr))
            continue;  // behind the camera: contributes nothing this iteration
        double w = 1.0;
        cost += robustCost(r.squaredNorm(), e.chi2Bound(), robust, w);
        if (H == nullptr)
            continue;
        H->noalias() += w * J.transpose() * J;
        b->noalias() += w * J.transpose() * r;
    }
    return cost;
}

/// T_cam_world moved by the left perturbation dx = [w, v].
Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T_cam_world, const Vector6& dx)
{
    Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
    const double angle = dx.head<3>().norm();
    if (angle > 1e-12)
        delta.linear() = Eigen::AngleAxisd(angle, dx.head<3>() / angle).toRotationMatrix();
    delta.translation() = dx.tail<3>();
    Eigen::Isometry3d T = delta * T_cam_world;
    // Keep the rotation orthonormal over many small updates.
    const Eigen::Quaterniond q(T.linear());
    T.linear() = q.normalized().toRotationMatrix();
    return T;
}

/// One pose-only Levenberg-Marquardt solve over the inlier edges (Huber loss while `robust`):
/// at most `iterations` trial steps, stopping once a step no longer changes the cost.
void solveRound(const std::vector<Edge>& edges, const std::vector<bool>& outlier,
                const Intrinsics& k, bool robust, int iterations, Eigen::Isometry3d& T_cam_world)
{
    constexpr double kRelativeCostTolerance = 1e-6;
    constexpr double kStepTolerance = 1e-10;
    Matrix6 H;
    Vector6 b;
    double cost = linearise(edges, outlier, k, T_cam_world, robust, &H, &b);
    double lambda = 1e-5 * H.diagonal().maxCoeff();
    for (int it = 0; it < iterations; ++it)
    {
        Matrix6 damped = H;
        damped.diagonal().array() += lambda;
        const Vector6 dx = damped.ldlt().solve(-b);
        if (!dx.allFinite() || dx.norm() < kStepTolerance)
            return;
        const Eigen::Isometry3d trial = perturbed(T_cam_world, dx);
        const double trialCost = linearise(edges, outlier, k, trial, robust, nullptr, nullptr);
        if (trialCost >= cost)
        {
            lambda *= 4.0;  // rejected: a shorter, more gradient-like step next
            continue;
        }
        const double decrease = (cost - trialCost) / std::max(cost, 1e-300);
        T_cam_world = trial;
        if (decrease < kRelativeCostTolerance)
            return;
        lambda = std::max(lambda / 3.0, 1e-12);
        cost = linearise(edges, outlier, k, T_cam_world, robust, &H, &b);
    }
}

/// Marks the edges behind the camera or beyond the chi-square bound; returns the inliers.
int classifyEdges(const std::vector<Edge>& edges, const Intrinsics& k,
                  const Eigen::Isometry3d& T_cam_world, std::vector<bool>& outlier)
{
    int inliers = 0;
    Eigen::Vector3d r;
    for (size_t i = 0; i < edges.size(); ++i)
    {
        const bool inFront = edgeResidual(edges[i], k, T_cam_world, r, nullptr);
        outlier[i] = !inFront || r.squaredNorm() > edges[i].chi2Bound();
        if (!outlier[i])
            inliers++;
    }
    return inliers;
}
}  // namespace

int optimizePose(Frame& frame, int rounds, int iterations)
{
    const std::vector<Edge> edges = collectEdges(frame);
    if (edges.size() < 3)
        return 0;
    const Intrinsics k{frame.camera.fx, frame.camera.fy, frame.camera.cx, frame.camera.cy,
                       frame.bf};
    Eigen::Isometry3d T_cam_world = frame.T_cam_world;
    std::vector<bool> outlier(edges.size(), false);
    // The robust cost is dropped for the last rounds, as ORB-SLAM does, once the gross
    // outliers are out.
    constexpr int kRobustRounds = 2;
    constexpr int kMinInliers = 10;
    int inliers = 0;
    for (int round = 0; round < rounds; ++round)
    {
        if (std::count(outlier.begin(), outlier.end(), false) < 3)
            break;
        solveRound(edges, outlier, k, round < kRobustRounds, iterations, T_cam_world);
        inliers = classifyEdges(edges, k, T_cam_world, outlier);
        if (inliers < kMinInliers)
            break;
    }
    frame.T_cam_world = T_cam_world;
    for (size_t i = 0; i < edges.size(); ++i)
        frame.outlier[edges[i].index] = outlier[i];
    return inliers;
}
}  // namespace smap::slam
