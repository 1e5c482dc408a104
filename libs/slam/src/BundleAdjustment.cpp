#include "smap/slam/BundleAdjustment.h"

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "ReprojectionCost.h"
#include "smap/slam/Map.h"
#include "smap/slam/MapCorrection.h"

namespace smap::slam
{
namespace
{
class AbortCallback : public ceres::IterationCallback
{
public:
    explicit AbortCallback(const std::atomic<bool>& abort) : abort_(abort) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override
    {
        return abort_.load() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
    }

private:
    const std::atomic<bool>& abort_;
};

enum class BaScope
{
    Local,
    Global
};

struct BaKeyFrame
{
    std::shared_ptr<KeyFrame> kf;
    std::array<double, 6> pose{};
    std::array<double, 6> tracked{};  // the pose before the adjustment
    bool fixed = false;
    CameraModel cam;
};
struct BaPoint
{
    std::shared_ptr<MapPoint> mp;
    std::array<double, 3> position{};
    std::array<double, 3> initial{};  // before the adjustment
};
struct BaObservation
{
    size_t keyframe;  // index into keyframes
    size_t point;     // index into points
    size_t keypoint;  // index in the keyframe
    Observation2D3 obs;
    bool outlier = false;
};

struct BaProblem
{
    std::vector<BaKeyFrame> kfs;
    std::vector<BaPoint> pts;
    std::vector<BaObservation> obs;
    std::map<uint64_t, size_t> kfIndex;

    // Hold the map mutex.
    void addKeyFrame(const Map& map, const KeyFrame& kf, bool fixed)
    {
        kfIndex[kf.id()] = kfs.size();
        BaKeyFrame b{map.allKeyFrames().at(kf.id()), {}, {}, fixed, CameraModel(kf.camera, kf.bf)};
        poseToParams(kf.T_cam_world(), b.pose.data());
        b.tracked = b.pose;
        kfs.push_back(b);
    }

    // The points of keyframes [0, nPoseKeyFrames) and all their observations (those of weight
    // zero left out); observing keyframes not in the problem yet join it held still. Hold the
    // map mutex.
    void addPointsOf(const Map& map, size_t nPoseKeyFrames)
    {
        std::map<uint64_t, size_t> ptIndex;
        for (size_t k = 0; k < nPoseKeyFrames; ++k)
        {
            for (const auto& mp : kfs[k].kf->points)
            {
                if (!mp || mp->isBad() || ptIndex.count(mp->id()))
                    continue;
                ptIndex[mp->id()] = pts.size();
                const std::array<double, 3> p{mp->position_world.x(), mp->position_world.y(),
                                              mp->position_world.z()};
                pts.push_back({mp, p, p});
            }
        }
        for (size_t p = 0; p < pts.size(); ++p)
        {
            for (const auto& [kfId, o] : pts[p].mp->observations())
            {
                if (!kfIndex.count(kfId))
                    addKeyFrame(map, *o.keyframe, true);
                const size_t k = kfIndex[kfId];
                const KeyFrame& kf = *o.keyframe;
                if (kf.weights[o.index] <= 0.0F)
                    continue;
                const auto& fs = kf.features;
                BaObservation b{k, p, o.index, {}};
                b.obs.u = fs.undistorted[o.index].x;
                b.obs.v = fs.undistorted[o.index].y;
                b.obs.ur = fs.hasDepth(o.index) ? fs.rightU[o.index] : -1.0;
                b.obs.sqrtInfo = std::sqrt(
                    fs.pyramid.invSigma2[static_cast<size_t>(fs.keypoints[o.index].octave)] *
                    kf.weights[o.index]);
                obs.push_back(b);
            }
        }
    }

    // A keyframe with fewer than `minShared` inlier observations of points that another
    // keyframe of the problem sees too holds the pose it had before the adjustment: the
    // adjustment knows less about it than tracking did when it placed it, and a few wrong
    // points would carry it off. Returns how many it newly holds.
    int holdWeaklyTied(int minShared)
    {
        std::vector<int> observers(pts.size(), 0), shared(kfs.size(), 0);
        for (const auto& o : obs)
            if (!o.outlier)
                observers[o.point]++;
        for (const auto& o : obs)
            if (!o.outlier && observers[o.point] > 1)
                shared[o.keyframe]++;
        int held = 0;
        for (size_t k = 0; k < kfs.size(); ++k)
        {
            if (!kfs[k].fixed && shared[k] < minShared)
            {
                kfs[k].fixed = true;
                kfs[k].pose = kfs[k].tracked;
                held++;
            }
        }
        return held;
    }

    // Every keyframe and point back where it was before the adjustment, no outliers.
    void restart()
    {
        for (auto& k : kfs)
            k.pose = k.tracked;
        for (auto& p : pts)
            p.position = p.initial;
        for (auto& o : obs)
            o.outlier = false;
    }

    // Gauge freedom: with no fixed keyframe, hold the oldest one.
    void holdGauge()
    {
        bool anyFixed = false;
        for (const auto& k : kfs)
            anyFixed = anyFixed || k.fixed;
        if (!anyFixed && !kfs.empty())
        {
            size_t oldest = 0;
            for (size_t k = 1; k < kfs.size(); ++k)
                if (kfs[k].kf->id() < kfs[oldest].kf->id())
                    oldest = k;
            kfs[oldest].fixed = true;
        }
    }
};

/// One Ceres solve over the inlier observations (Huber loss when robust); true when the
/// callback aborted it.
bool solveOnce(BaProblem& pb, int iterations, bool robust, AbortCallback& callback)
{
    ceres::Problem problem;
    for (auto& o : pb.obs)
    {
        if (o.outlier)
            continue;
        auto& kf = pb.kfs[o.keyframe];
        ceres::LossFunction* loss =
            robust ? new ceres::HuberLoss(std::sqrt(o.obs.stereo() ? kChi2Stereo : kChi2Mono))
                   : nullptr;
        if (o.obs.stereo())
            problem.AddResidualBlock(
                new ceres::AutoDiffCostFunction<ReprojectionResidual<3>, 3, 6, 3>(
                    new ReprojectionResidual<3>(o.obs, kf.cam)),
                loss, kf.pose.data(), pb.pts[o.point].position.data());
        else
            problem.AddResidualBlock(
                new ceres::AutoDiffCostFunction<ReprojectionResidual<2>, 2, 6, 3>(
                    new ReprojectionResidual<2>(o.obs, kf.cam)),
                loss, kf.pose.data(), pb.pts[o.point].position.data());
    }
    for (auto& kf : pb.kfs)
        if (kf.fixed && problem.HasParameterBlock(kf.pose.data()))
            problem.SetParameterBlockConstant(kf.pose.data());
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_SCHUR;
    options.max_num_iterations = iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.callbacks.push_back(&callback);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    return summary.termination_type == ceres::USER_FAILURE;
}

/// Marks the observations behind their camera or beyond the chi-square bound as outliers.
void classifyOutliers(BaProblem& pb)
{
    for (auto& o : pb.obs)
    {
        bool inFront = false;
        const double chi2 =
            reprojectionChi2(pb.kfs[o.keyframe].pose.data(), pb.pts[o.point].position.data(), o.obs,
                             pb.kfs[o.keyframe].cam, inFront);
        o.outlier = !inFront || chi2 > (o.obs.stereo() ? kChi2Stereo : kChi2Mono);
    }
}

/// Removes the observations classified as outliers from the map. Hold the map mutex.
int removeOutliers(const BaProblem& pb)
{
    int removed = 0;
    for (const auto& o : pb.obs)
    {
        if (!o.outlier)
            continue;
        KeyFrame& kf = *pb.kfs[o.keyframe].kf;
        const auto& mp = pb.pts[o.point].mp;
        if (kf.isBad() || mp->isBad() || kf.points[o.keypoint] != mp)
            continue;
        kf.points[o.keypoint].reset();
        mp->eraseObservation(&kf);
        removed++;
    }
    return removed;
}

/// The problem's points written back. Hold the map mutex.
void writePoints(const BaProblem& pb)
{
    for (const auto& p : pb.pts)
    {
        if (p.mp->isBad())
            continue;
        p.mp->position_world = Eigen::Vector3d(p.position[0], p.position[1], p.position[2]);
        p.mp->updateNormalAndDepth();
    }
}

/// Local: the problem's keyframes and points as solved. Global: the same, and what tracking
/// added to the map while it was solved follows the newest keyframe of the problem
/// (MapCorrection.h), so that it stays where it was against its neighbours; tracking is told
/// to follow. Under the map mutex; returns the outlier observations removed.
int writeBack(const BaProblem& pb, Map& map, BaScope scope)
{
    std::lock_guard<std::mutex> lock(map.mutex());
    const int removed = removeOutliers(pb);
    if (scope == BaScope::Global)
    {
        std::map<uint64_t, Eigen::Isometry3d> old, solved;
        std::set<uint64_t> placed;
        for (const auto& k : pb.kfs)
        {
            old[k.kf->id()] = k.kf->T_cam_world();
            solved[k.kf->id()] = k.fixed ? k.kf->T_cam_world() : paramsToPose(k.pose.data());
        }
        for (const auto& p : pb.pts)
            placed.insert(p.mp->id());
        if (!old.empty())
            applyCorrections(map, correctionsBetween(old, solved), placed);
        map.noteCorrection();
    }
    else
    {
        for (const auto& k : pb.kfs)
            if (!k.fixed && !k.kf->isBad())
                k.kf->setPose(paramsToPose(k.pose.data()));
    }
    writePoints(pb);
    return removed;
}

void countKeyFrames(const BaProblem& pb, BundleAdjustmentStats& stats)
{
    stats.keyframes = stats.fixedKeyframes = 0;
    for (const auto& k : pb.kfs)
        (k.fixed ? stats.fixedKeyframes : stats.keyframes)++;
}

// Weakly tied keyframes held, robust solve, outliers classified. Keyframes that the outliers
// leave weakly tied are held too and the robust solve starts again from the poses and points
// before (their wrong observations must not have moved the rest). Plain solve, classified
// again; then the result is written back under the map mutex.
BundleAdjustmentStats solveAndWriteBack(BaProblem& pb, Map& map, BaScope scope,
                                        int robust_iterations, int refine_iterations,
                                        int min_shared_observations, const std::atomic<bool>& abort)
{
    BundleAdjustmentStats stats;
    stats.weaklyTiedHeld = pb.holdWeaklyTied(min_shared_observations);
    pb.holdGauge();
    countKeyFrames(pb, stats);
    stats.points = static_cast<int>(pb.pts.size());
    stats.observations = static_cast<int>(pb.obs.size());
    if (stats.keyframes == 0 || pb.pts.empty())
        return stats;
    AbortCallback callback(abort);
    const auto solve = [&](int iterations, bool robust)
    {
        if (iterations > 0 && !abort.load())
            stats.aborted = solveOnce(pb, iterations, robust, callback) || stats.aborted;
        classifyOutliers(pb);
    };
    solve(robust_iterations, true);
    const int leftWeak = pb.holdWeaklyTied(min_shared_observations);
    if (leftWeak > 0)
    {
        stats.weaklyTiedHeld += leftWeak;
        pb.restart();
        solve(robust_iterations, true);
    }
    solve(refine_iterations, false);
    countKeyFrames(pb, stats);
    stats.aborted = stats.aborted || abort.load();
    stats.outliersRemoved = writeBack(pb, map, scope);
    return stats;
}
}  // namespace

BundleAdjustmentStats localBundleAdjustment(const std::shared_ptr<KeyFrame>& keyframe, Map& map,
                                            const LocalMappingParameters& params,
                                            const std::atomic<bool>& abort)
{
    BaProblem pb;
    {
        std::lock_guard<std::mutex> lock(map.mutex());
        if (keyframe->isBad())
            return {};
        // The origin of each part (the first keyframe of the map, a re-anchor) defines its frame
        // and never moves (as the first keyframe in ORB-SLAM).
        pb.addKeyFrame(map, *keyframe, keyframe->isPartOrigin());
        for (KeyFrame* kf : keyframe->bestCovisibles(params.ba_max_keyframes - 1))
            if (!kf->isBad())
                pb.addKeyFrame(map, *kf, kf->isPartOrigin());
        pb.addPointsOf(map, pb.kfs.size());
    }
    return solveAndWriteBack(pb, map, BaScope::Local, params.ba_iterations,
                             params.ba_refine_iterations, params.ba_min_shared_observations, abort);
}

BundleAdjustmentStats globalBundleAdjustment(Map& map, int iterations, int min_shared_observations,
                                             const std::atomic<bool>& abort)
{
    BaProblem pb;
    {
        std::lock_guard<std::mutex> lock(map.mutex());
        for (const auto& [id, kf] : map.keyframes())
            if (!kf->isBad())
                pb.addKeyFrame(map, *kf, kf->isPartOrigin());
        pb.addPointsOf(map, pb.kfs.size());
    }
    return solveAndWriteBack(pb, map, BaScope::Global, iterations, iterations,
                             min_shared_observations, abort);
}
}  // namespace smap::slam
