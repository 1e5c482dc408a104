#include "smap/slam/PoseGraph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>
#include <stdexcept>

namespace smap::slam
{
namespace
{
/// Pose block: angle-axis (3) + translation (3) of T_cam_world, as in bundle adjustment.
using PoseBlock = std::array<double, 6>;

PoseBlock toBlock(const Eigen::Isometry3d& T)
{
    PoseBlock b{};
    const Eigen::AngleAxisd aa(T.rotation());
    const Eigen::Vector3d v = aa.angle() * aa.axis();
    for (int k = 0; k < 3; ++k)
    {
        b[static_cast<size_t>(k)] = v(k);
        b[static_cast<size_t>(k) + 3] = T.translation()(k);
    }
    return b;
}

Eigen::Isometry3d fromBlock(const PoseBlock& b)
{
    const Eigen::Vector3d v(b[0], b[1], b[2]);
    const double angle = v.norm();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (angle > 0.0)
        T.linear() = Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
    T.translation() = Eigen::Vector3d(b[3], b[4], b[5]);
    return T;
}

struct RelativePoseResidual
{
    RelativePoseResidual(const Eigen::Isometry3d& T_i_j, double weight) : w(weight)
    {
        const Eigen::Quaterniond q(T_i_j.rotation());
        // Inverse of the measurement: rotation conj(q), translation -R^T t.
        qInv = {q.w(), -q.x(), -q.y(), -q.z()};
        const Eigen::Vector3d t = -(T_i_j.rotation().transpose() * T_i_j.translation());
        tInv = {t.x(), t.y(), t.z()};
    }

    template <typename T>
    bool operator()(const T* const pi, const T* const pj, T* residual) const
    {
        // E = M^-1 * T_i * T_j^-1, with T_j^-1 = (R_j^T, -R_j^T t_j).
        T qi[4], qj[4];
        ceres::AngleAxisToQuaternion(pi, qi);
        ceres::AngleAxisToQuaternion(pj, qj);
        const T qjInv[4] = {qj[0], -qj[1], -qj[2], -qj[3]};
        T qRel[4];  // R_i R_j^T
        ceres::QuaternionProduct(qi, qjInv, qRel);
        T tj[3] = {pj[3], pj[4], pj[5]}, rtj[3];
        ceres::UnitQuaternionRotatePoint(qRel, tj, rtj);
        const T tRel[3] = {pi[3] - rtj[0], pi[4] - rtj[1], pi[5] - rtj[2]};
        const T qm[4] = {T(qInv[0]), T(qInv[1]), T(qInv[2]), T(qInv[3])};
        T qE[4], tE[3];
        ceres::QuaternionProduct(qm, qRel, qE);
        ceres::UnitQuaternionRotatePoint(qm, tRel, tE);
        const T sign = qE[0] < T(0) ? T(-1) : T(1);
        for (int k = 0; k < 3; ++k)
        {
            residual[k] = T(2.0 * w) * sign * qE[k + 1];
            residual[k + 3] = T(w) * (tE[k] + T(tInv[static_cast<size_t>(k)]));
        }
        return true;
    }

    std::array<double, 4> qInv{};
    std::array<double, 3> tInv{};
    double w;
};
}  // namespace

PoseGraphResult optimisePoseGraph(std::map<uint64_t, Eigen::Isometry3d>& poses,
                                  const std::vector<PoseGraphEdge>& edges,
                                  const std::set<uint64_t>& fixed, int max_iterations)
{
    if (fixed.empty())
        throw std::invalid_argument("optimisePoseGraph: hold at least one pose still");
    std::map<uint64_t, PoseBlock> blocks;
    for (const auto& [id, T] : poses)
        blocks[id] = toBlock(T);
    ceres::Problem problem;
    for (const auto& e : edges)
    {
        auto bi = blocks.find(e.i), bj = blocks.find(e.j);
        if (bi == blocks.end() || bj == blocks.end() || e.i == e.j)
            continue;
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, 6, 6>(
                                     new RelativePoseResidual(e.T_i_j, e.weight)),
                                 nullptr, bi->second.data(), bj->second.data());
    }
    for (uint64_t id : fixed)
    {
        auto b = blocks.find(id);
        if (b != blocks.end() && problem.HasParameterBlock(b->second.data()))
            problem.SetParameterBlockConstant(b->second.data());
    }
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    for (auto& [id, T] : poses)
        T = fromBlock(blocks[id]);
    return {static_cast<int>(summary.iterations.size()), summary.initial_cost, summary.final_cost};
}
}  // namespace smap::slam
