#include "smap/slam/PoseOptimizer.h"

#include <cmath>
#include <vector>

#include "ReprojectionCost.h"
#include "smap/slam/Frame.h"
#include "smap/slam/MapPoint.h"

namespace smap::slam
{
int optimizePose(Frame& frame, int rounds, int iterations)
{
    struct Edge
    {
        size_t index;
        Observation2D3 obs;
        Eigen::Vector3d point;
    };
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

    int inliers = 0;
    for (int round = 0; round < rounds; ++round)
    {
        ceres::Problem problem;
        int used = 0;
        for (size_t k = 0; k < edges.size(); ++k)
        {
            if (outlier[k])
                continue;
            const Edge& e = edges[k];
            // The robust cost is dropped for the last rounds, as ORB-SLAM does, once the
            // gross outliers are out.
            ceres::LossFunction* loss = nullptr;
            if (round < 2)
                loss = new ceres::HuberLoss(std::sqrt(e.obs.stereo() ? kChi2Stereo : kChi2Mono));
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
            break;
        ceres::Solver::Summary summary;
        ceres::Solve(options, &problem, &summary);

        inliers = 0;
        for (size_t k = 0; k < edges.size(); ++k)
        {
            const Edge& e = edges[k];
            bool inFront = false;
            const double chi2 = reprojectionChi2(pose, e.point.data(), e.obs, cam, inFront);
            outlier[k] = !inFront || chi2 > (e.obs.stereo() ? kChi2Stereo : kChi2Mono);
            if (!outlier[k])
                inliers++;
        }
        if (inliers < 10)
            break;
    }
    frame.T_cam_world = paramsToPose(pose);
    for (size_t k = 0; k < edges.size(); ++k)
        frame.outlier[edges[k].index] = outlier[k];
    return inliers;
}
}  // namespace smap::slam
