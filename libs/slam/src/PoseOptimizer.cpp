#include "smap/slam/PoseOptimizer.h"

#include <cmath>
#include <vector>

#include "ReprojectionCost.h"
#include "smap/slam/Frame.h"
#include "smap/slam/MapPoint.h"

namespace smap::slam
{
namespace
{
/// A matched keypoint of the frame: its observation and its map point's position.
struct Edge
{
    size_t index;
    Observation2D3 obs;
    Eigen::Vector3d point;
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
        Edge e{i, {}, mp->position_world};
        e.obs.u = fs.undistorted[i].x;
        e.obs.v = fs.undistorted[i].y;
        e.obs.ur = fs.hasDepth(i) ? fs.rightU[i] : -1.0;
        e.obs.sqrtInfo = std::sqrt(
            fs.pyramid.invSigma2[static_cast<size_t>(fs.keypoints[i].octave)] * frame.weights[i]);
        edges.push_back(e);
        frame.outlier[i] = false;
    }
    return edges;
}

/// One pose-only solve over the inlier edges (Huber loss while `robust`); false when fewer
/// than 3 edges remain.
bool solveRound(const std::vector<Edge>& edges, const std::vector<bool>& outlier,
                const CameraModel& cam, bool robust, const ceres::Solver::Options& options,
                double* pose)
{
    ceres::Problem problem;
    int used = 0;
    for (size_t k = 0; k < edges.size(); ++k)
    {
        if (outlier[k])
            continue;
        const Edge& e = edges[k];
        ceres::LossFunction* loss =
            robust ? new ceres::HuberLoss(std::sqrt(e.obs.stereo() ? kChi2Stereo : kChi2Mono))
                   : nullptr;
        if (e.obs.stereo())
            problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PoseOnlyResidual<3>, 3, 6>(
                                         new PoseOnlyResidual<3>(e.obs, cam, e.point)),
                                     loss, pose);
        else
            problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PoseOnlyResidual<2>, 2, 6>(
                                         new PoseOnlyResidual<2>(e.obs, cam, e.point)),
                                     loss, pose);
        used++;
    }
    if (used < 3)
        return false;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    return true;
}

/// Marks the edges behind the camera or beyond the chi-square bound; returns the inliers.
int classifyEdges(const std::vector<Edge>& edges, const CameraModel& cam, const double* pose,
                  std::vector<bool>& outlier)
{
    int inliers = 0;
    for (size_t k = 0; k < edges.size(); ++k)
    {
        const Edge& e = edges[k];
        bool inFront = false;
        const double chi2 = reprojectionChi2(pose, e.point.data(), e.obs, cam, inFront);
        outlier[k] = !inFront || chi2 > (e.obs.stereo() ? kChi2Stereo : kChi2Mono);
        if (!outlier[k])
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
    const CameraModel cam(frame.camera, frame.bf);
    double pose[6];
    poseToParams(frame.T_cam_world, pose);
    std::vector<bool> outlier(edges.size(), false);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    // The robust cost is dropped for the last rounds, as ORB-SLAM does, once the gross
    // outliers are out.
    constexpr int kRobustRounds = 2;
    constexpr int kMinInliers = 10;
    int inliers = 0;
    for (int round = 0; round < rounds; ++round)
    {
        if (!solveRound(edges, outlier, cam, round < kRobustRounds, options, pose))
            break;
        inliers = classifyEdges(edges, cam, pose, outlier);
        if (inliers < kMinInliers)
            break;
    }
    frame.T_cam_world = paramsToPose(pose);
    for (size_t k = 0; k < edges.size(); ++k)
        frame.outlier[edges[k].index] = outlier[k];
    return inliers;
}
}  // namespace smap::slam
