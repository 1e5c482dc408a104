#include "smap/dynamic/EgoMotion.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <utility>
#include <vector>

#include "smap/core/Median.h"
#include "smap/features/DescriptorMatcher.h"
#include "smap/features/FeatureGrid.h"

namespace smap::dynamic
{
namespace
{
/// The previous keypoints in a grid for radius queries (32 px cells: the match radius is
/// large). Keypoints marked in `excluded` (one entry per previous keypoint, or empty) are moved
/// far outside the image, so that no query radius reaches them.
features::FeatureGrid previousGrid(const features::FeatureSet& previous,
                                   const core::PinholeCamera& camera,
                                   const std::vector<bool>& excluded = {})
{
    std::vector<int> levels;
    levels.reserve(previous.size());
    for (const auto& kp : previous.keypoints)
        levels.push_back(kp.octave);
    std::vector<cv::Point2f> points = previous.undistorted;
    if (excluded.size() == points.size())
        for (size_t i = 0; i < points.size(); ++i)
            if (excluded[i])
                points[i] = cv::Point2f(-1e6F, -1e6F);
    return {std::move(points), std::move(levels), camera.width, camera.height, 32};
}

/// Ratio-test matches of current keypoints (query) to previous ones (train, in `grid`) within
/// match_radius. `rows`: the current keypoints to query (empty: all).
std::vector<features::DescriptorMatch> frameToFrameMatches(const features::FeatureSet& previous,
                                                           const features::FeatureGrid& grid,
                                                           const features::FeatureSet& current,
                                                           const DynamicParameters& params,
                                                           const std::vector<size_t>& rows)
{
    return features::matchWithinRadius(
        current.descriptors, current.keypoints, current.undistorted, previous.descriptors, grid,
        static_cast<float>(params.match_radius), static_cast<float>(params.match_ratio), 64, rows);
}

/// At most `max_queries` of `n` keypoints, spread evenly over the (grid-ordered) set, and the
/// others; both empty when max_queries is 0 or not below n (then all are queried at once).
std::pair<std::vector<size_t>, std::vector<size_t>> splitQueries(size_t n, int max_queries)
{
    std::vector<size_t> first, rest;
    if (max_queries <= 0 || n <= static_cast<size_t>(max_queries))
        return {first, rest};
    std::vector<bool> taken(n, false);
    const double step = static_cast<double>(n) / max_queries;
    for (int k = 0; k < max_queries; ++k)
    {
        const auto i = static_cast<size_t>(k * step);
        first.push_back(i);
        taken[i] = true;
    }
    for (size_t i = 0; i < n; ++i)
        if (!taken[i])
            rest.push_back(i);
    return {first, rest};
}

/// Matches whose reprojection under T_cur_prev lies within `tolerance` px.
int support(const Eigen::Isometry3d& T_cur_prev, const std::vector<cv::Point3f>& object,
            const std::vector<cv::Point2f>& image, const core::PinholeCamera& camera,
            double tolerance)
{
    int n = 0;
    for (size_t k = 0; k < object.size(); ++k)
    {
        const Eigen::Vector3d X =
            T_cur_prev * Eigen::Vector3d(object[k].x, object[k].y, object[k].z);
        if (X.z() <= 0.05)
            continue;
        const double du = camera.fx * X.x() / X.z() + camera.cx - image[k].x;
        const double dv = camera.fy * X.y() / X.z() + camera.cy - image[k].y;
        n += du * du + dv * dv <= tolerance * tolerance ? 1 : 0;
    }
    return n;
}
}  // namespace

namespace
{
/// The relative pose of the stacked essential matrix that puts most RANSAC inliers in front of
/// both cameras (the five-point solver may return several): R, unit t, its inlier mask.
struct RelativePose
{
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    cv::Mat mask;
    int inliers = 0;
};

RelativePose bestEssentialPose(const cv::Mat& E, const std::vector<cv::Point2f>& prevPts,
                               const std::vector<cv::Point2f>& curPts, const cv::Mat& K,
                               const cv::Mat& mask)
{
    RelativePose best;
    cv::Mat R, t;
    for (int k = 0; k < E.rows / 3; ++k)
    {
        cv::Mat Rk, tk, maskK = mask.clone();
        // Consecutive frames have a short baseline: the default cheirality distance limit
        // (50 baselines) would reject every point, so only "in front" is checked.
        cv::Mat triangulated;
        const int n = cv::recoverPose(E.rowRange(3 * k, 3 * k + 3), prevPts, curPts, K, Rk, tk, 1e7,
                                      maskK, triangulated);
        if (n > best.inliers)
        {
            best.inliers = n;
            R = Rk;
            t = tk;
            best.mask = maskK;
        }
    }
    if (best.inliers == 0)
        return best;
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
            best.R(r, c) = R.at<double>(r, c);
        best.t(r) = t.at<double>(r);
    }
    best.t.normalize();
    return best;
}

/// The metric length of the unit translation from the inliers' depth: 3D-3D where both frames
/// have depth, else the previous point moved along t onto the current pixel; (length,
/// samples), nullopt with fewer than 5 samples of either kind.
std::optional<std::pair<double, int>> metricScale(
    const std::vector<features::DescriptorMatch>& matches, const RelativePose& pose,
    const features::FeatureSet& previous, const features::FeatureSet& current,
    const std::vector<cv::Point2f>& prevPts, const std::vector<cv::Point2f>& curPts,
    const core::PinholeCamera& camera)
{
    constexpr size_t kMinSamples = 5;
    const Eigen::Matrix3d& Re = pose.R;
    const Eigen::Vector3d& te = pose.t;
    std::vector<double> s3, s2;
    for (size_t k = 0; k < matches.size(); ++k)
    {
        if (pose.mask.at<uint8_t>(static_cast<int>(k)) == 0)
            continue;
        const size_t ip = matches[k].train, ic = matches[k].query;
        const float zp = previous.depth.empty() ? 0.0F : previous.depth[ip];
        if (zp <= 0.0F)
            continue;
        const Eigen::Vector3d a =
            Re * camera.unproject(prevPts[k].x, prevPts[k].y, static_cast<double>(zp));
        const float zc = current.depth.empty() ? 0.0F : current.depth[ic];
        if (zc > 0.0F)
        {
            const Eigen::Vector3d c =
                camera.unproject(curPts[k].x, curPts[k].y, static_cast<double>(zc));
            s3.push_back(te.dot(c - a));
            continue;
        }
        // a + s t projects to the measured pixel: solve the better-conditioned coordinate.
        const double xn = (curPts[k].x - camera.cx) / camera.fx;
        const double yn = (curPts[k].y - camera.cy) / camera.fy;
        const double dx = te.x() - xn * te.z(), dy = te.y() - yn * te.z();
        if (std::abs(dx) >= std::abs(dy) && std::abs(dx) > 1e-3)
            s2.push_back((xn * a.z() - a.x()) / dx);
        else if (std::abs(dy) > 1e-3)
            s2.push_back((yn * a.z() - a.y()) / dy);
    }
    if (s3.size() >= kMinSamples)
        return std::make_pair(core::upperMedianInPlace(s3), static_cast<int>(s3.size()));
    if (s2.size() >= kMinSamples)
        return std::make_pair(core::upperMedianInPlace(s2), static_cast<int>(s2.size()));
    return std::nullopt;
}
}  // namespace

EgoMotion estimateEgoMotionFivePoint(const features::FeatureSet& previous,
                                     const features::FeatureSet& current,
                                     const core::PinholeCamera& camera,
                                     const DynamicParameters& params)
{
    constexpr size_t kMinPoints = 8;
    EgoMotion out;
    if (previous.size() < kMinPoints || current.size() < kMinPoints)
        return out;
    const auto matches =
        frameToFrameMatches(previous, previousGrid(previous, camera), current, params, {});
    out.matches = static_cast<int>(matches.size());
    if (matches.size() < kMinPoints)
        return out;
    std::vector<cv::Point2f> prevPts, curPts;
    for (const auto& m : matches)
    {
        prevPts.push_back(previous.undistorted[m.train]);
        curPts.push_back(current.undistorted[m.query]);
    }
    const cv::Mat K = camera.cameraMatrix();
    cv::Mat mask;
    const cv::Mat E =
        cv::findEssentialMat(prevPts, curPts, K, cv::RANSAC, params.essential_confidence,
                             params.essential_threshold, mask);
    if (E.cols != 3 || E.rows < 3 || E.rows % 3 != 0)
        return out;  // degenerate
    const RelativePose pose = bestEssentialPose(E, prevPts, curPts, K, mask);
    out.inliers = pose.inliers;
    if (out.inliers < static_cast<int>(kMinPoints))
        return out;
    const auto scale = metricScale(matches, pose, previous, current, prevPts, curPts, camera);
    if (!scale)
        return out;
    out.scaleSamples = scale->second;
    out.T_cur_prev.linear() = pose.R;
    out.T_cur_prev.translation() = scale->first * pose.t;
    out.valid = true;
    return out;
}

namespace
{
/// 3D points of the previous frame (from its depth) and where the current frame sees them.
struct Correspondences
{
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    int matches = 0;
};

Correspondences pnpCorrespondences(const features::FeatureSet& previous,
                                   const features::FeatureSet& current,
                                   const core::PinholeCamera& camera,
                                   const DynamicParameters& params,
                                   const std::vector<bool>& previous_dynamic)
{
    Correspondences c;
    const features::FeatureGrid grid = previousGrid(previous, camera, previous_dynamic);
    auto addMatches = [&](const std::vector<size_t>& rows)
    {
        const auto matches = frameToFrameMatches(previous, grid, current, params, rows);
        c.matches += static_cast<int>(matches.size());
        for (const auto& m : matches)
        {
            const float z = previous.depth.empty() ? 0.0F : previous.depth[m.train];
            if (z <= 0.0F)
                continue;
            const auto& p = previous.undistorted[m.train];
            const Eigen::Vector3d X = camera.unproject(p.x, p.y, static_cast<double>(z));
            c.object.emplace_back(static_cast<float>(X.x()), static_cast<float>(X.y()),
                                  static_cast<float>(X.z()));
            c.image.push_back(current.undistorted[m.query]);
        }
    };
    const auto [first, rest] = splitQueries(current.size(), params.ego_max_queries);
    addMatches(first);
    // Where movers fill much of the view, most of the first queries land on them and find
    // nothing among the previous static keypoints: query the others too.
    constexpr size_t kEnoughMatches = 60;
    if (c.object.size() < kEnoughMatches && !rest.empty())
        addMatches(rest);
    return c;
}

/// Re-selects the inliers under the pose and fits it to all of them by least squares
/// (Gauss-Newton), three rounds.
void refineOnInliers(const Correspondences& c, const core::PinholeCamera& camera,
                     const DynamicParameters& params, EgoMotion& out)
{
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> pixels;
    const double th2 = params.pnp_threshold * params.pnp_threshold;
    for (int round = 0; round < 3; ++round)
    {
        points.clear();
        pixels.clear();
        for (size_t k = 0; k < c.object.size(); ++k)
        {
            const Eigen::Vector3d X(c.object[k].x, c.object[k].y, c.object[k].z);
            const Eigen::Vector3d P = out.T_cur_prev * X;
            if (P.z() <= 0.05)
                continue;
            const Eigen::Vector2d uv(c.image[k].x, c.image[k].y);
            if ((camera.project(P) - uv).squaredNorm() <= th2)
            {
                points.push_back(X);
                pixels.push_back(uv);
            }
        }
        if (points.size() < 12)
            break;
        out.inliers = static_cast<int>(points.size());
        const auto fitted = refinePose(points, pixels, camera, out.T_cur_prev);
        if (!fitted)
            break;
        out.T_cur_prev = *fitted;
    }
}

/// Whether the prior (the previous frame's motion) beats the RANSAC pose: more support when
/// RANSAC's pose is plausible under the constant-velocity gate; when not, a quarter of its
/// support, or RANSAC's support under ego_gate_min_support (a few matches on people must not
/// make the camera jump).
bool priorWins(const Eigen::Isometry3d& prior, const EgoMotion& ransac, const Correspondences& c,
               const core::PinholeCamera& camera, const DynamicParameters& params, double tolerance)
{
    const int priorSupport = support(prior, c.object, c.image, camera, tolerance);
    const int ransacSupport = support(ransac.T_cur_prev, c.object, c.image, camera, tolerance);
    const Eigen::Isometry3d change = prior.inverse() * ransac.T_cur_prev;
    const double degrees = Eigen::AngleAxisd(change.linear()).angle() * 180.0 / M_PI;
    const bool gated = params.ego_gate_translation > 0.0 && params.ego_gate_rotation_deg > 0.0;
    const bool plausible = !gated || (change.translation().norm() <= params.ego_gate_translation &&
                                      degrees <= params.ego_gate_rotation_deg);
    if (plausible)
        return priorSupport > ransacSupport;
    return 4 * priorSupport >= ransacSupport || ransacSupport < params.ego_gate_min_support;
}
}  // namespace

EgoMotion estimateEgoMotionDepthPnp(const features::FeatureSet& previous,
                                    const features::FeatureSet& current,
                                    const core::PinholeCamera& camera,
                                    const DynamicParameters& params, bool refine,
                                    const std::vector<bool>& previous_dynamic,
                                    const std::optional<Eigen::Isometry3d>& prior)
{
    constexpr size_t kMinCorrespondences = 12;
    EgoMotion out;
    const Correspondences c =
        pnpCorrespondences(previous, current, camera, params, previous_dynamic);
    out.matches = c.matches;
    out.scaleSamples = static_cast<int>(c.object.size());
    // The prior competes with the RANSAC solution: the one more matches agree with, within
    // 3 x pnp_threshold, wins. It stands in where RANSAC fails.
    const double tolerance = 3.0 * params.pnp_threshold;
    auto usePrior = [&]()
    {
        out.T_cur_prev = *prior;
        out.inliers = support(*prior, c.object, c.image, camera, tolerance);
        out.fromPrior = true;
        out.valid = true;
        return out;
    };
    if (c.object.size() < kMinCorrespondences)
        return prior ? usePrior() : out;
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    if (!cv::solvePnPRansac(c.object, c.image, camera.cameraMatrix(), cv::noArray(), rvec, tvec,
                            false, 100, static_cast<float>(params.pnp_threshold), 0.99, inliers,
                            cv::SOLVEPNP_AP3P) ||
        inliers.size() < kMinCorrespondences)
        return prior ? usePrior() : out;
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    for (int r = 0; r < 3; ++r)
    {
        for (int col = 0; col < 3; ++col)
            out.T_cur_prev.linear()(r, col) = R.at<double>(r, col);
        out.T_cur_prev.translation()(r) = tvec.at<double>(r);
    }
    out.inliers = static_cast<int>(inliers.size());
    out.valid = true;
    if (refine)
        refineOnInliers(c, camera, params, out);
    if (prior && priorWins(*prior, out, c, camera, params, tolerance))
        return usePrior();
    return out;
}

std::optional<Eigen::Isometry3d> refinePose(const std::vector<Eigen::Vector3d>& points_source,
                                            const std::vector<Eigen::Vector2d>& pixels_target,
                                            const core::PinholeCamera& camera,
                                            const Eigen::Isometry3d& T_target_source,
                                            int max_iterations)
{
    if (points_source.size() != pixels_target.size() || points_source.size() < 6)
        return std::nullopt;
    Eigen::Isometry3d T = T_target_source;
    for (int it = 0; it < max_iterations; ++it)
    {
        // Left perturbation T <- exp(delta) T, delta = (rotation w, translation v): a point
        // P = T X moves by -[P]x w + v.
        Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
        Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
        for (size_t k = 0; k < points_source.size(); ++k)
        {
            const Eigen::Vector3d P = T * points_source[k];
            if (P.z() <= 1e-6)
                return std::nullopt;
            const double iz = 1.0 / P.z();
            const Eigen::Vector2d r = camera.project(P) - pixels_target[k];
            Eigen::Matrix<double, 2, 3> dproj;
            dproj << camera.fx * iz, 0.0, -camera.fx * P.x() * iz * iz, 0.0, camera.fy * iz,
                -camera.fy * P.y() * iz * iz;
            Eigen::Matrix<double, 3, 6> dP;
            dP.leftCols<3>() << 0.0, P.z(), -P.y(), -P.z(), 0.0, P.x(), P.y(), -P.x(), 0.0;
            dP.rightCols<3>().setIdentity();
            const Eigen::Matrix<double, 2, 6> J = dproj * dP;
            H.noalias() += J.transpose() * J;
            g.noalias() += J.transpose() * r;
        }
        const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(H);
        if (ldlt.info() != Eigen::Success || !ldlt.isPositive())
            return std::nullopt;
        const Eigen::Matrix<double, 6, 1> delta = ldlt.solve(-g);
        if (!delta.allFinite())
            return std::nullopt;
        const Eigen::Vector3d w = delta.head<3>();
        const double angle = w.norm();
        const Eigen::Matrix3d dR = angle > 1e-12
                                       ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                       : Eigen::Matrix3d::Identity();
        Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
        step.linear() = dR;
        step.translation() = delta.tail<3>();
        T = step * T;
        if (angle < 1e-9 && delta.tail<3>().norm() < 1e-9)
            break;
    }
    // Keep the rotation orthonormal after the updates.
    const Eigen::Quaterniond q(T.linear());
    T.linear() = q.normalized().toRotationMatrix();
    return T;
}
}  // namespace smap::dynamic
