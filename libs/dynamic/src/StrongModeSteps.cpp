#include "StrongModeSteps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/video/tracking.hpp>

#include "smap/dynamic/EgoMotion.h"

namespace smap::dynamic::strong
{
namespace
{
cv::Point3f toCv(const Eigen::Vector3d& X)
{
    return {static_cast<float>(X.x()), static_cast<float>(X.y()), static_cast<float>(X.z())};
}

float median(std::vector<float> v)
{
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

/// Nearest and farthest valid depth within kDepthSearchRadius of a pixel; (max, 0) when none.
std::pair<float, float> depthRangeAround(const cv::Mat& depth, const cv::Point2f& pt)
{
    float zNear = std::numeric_limits<float>::max(), zFar = 0.0F;
    const int u0 = cvRound(pt.x), v0 = cvRound(pt.y);
    const int r = kDepthSearchRadius;
    for (int v = std::max(0, v0 - r); v <= std::min(depth.rows - 1, v0 + r); ++v)
    {
        for (int u = std::max(0, u0 - r); u <= std::min(depth.cols - 1, u0 + r); ++u)
        {
            const float d = depth.at<float>(v, u);
            if (d > 0.0F)
            {
                zNear = std::min(zNear, d);
                zFar = std::max(zFar, d);
            }
        }
    }
    return {zNear, zFar};
}

/// Points in the reference camera's frame to its (distorted) pixels.
void toReferencePixels(const core::PinholeCamera& camera, const std::vector<cv::Point3f>& points,
                       std::vector<cv::Point2f>& out)
{
    out.clear();
    if (points.empty())
        return;
    if (camera.hasDistortion())
    {
        cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera.cameraMatrix(),
                          camera.distCoeffs(), out);
        return;
    }
    out.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i)
    {
        const Eigen::Vector2d uv =
            camera.project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
        out[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
}

/// Current-frame points moved into the reference camera and projected; `depthOut` (when given)
/// receives their depth there. Points behind the reference camera land far outside the image,
/// so they get no evidence.
void projectIntoReference(const core::PinholeCamera& camera, const Eigen::Isometry3d& T_prev_cur,
                          const std::vector<cv::Point3f>& points_cur, std::vector<cv::Point2f>& out,
                          std::vector<float>* depthOut)
{
    std::vector<cv::Point3f> points_prev(points_cur.size());
    for (size_t i = 0; i < points_cur.size(); ++i)
    {
        const Eigen::Vector3d X =
            T_prev_cur * Eigen::Vector3d(points_cur[i].x, points_cur[i].y, points_cur[i].z);
        if (depthOut)
            (*depthOut)[i] = static_cast<float>(X.z());
        points_prev[i] = X.z() > kMinReferenceDepth ? toCv(X) : cv::Point3f(1e4F, 1e4F, 1.0F);
    }
    toReferencePixels(camera, points_prev, out);
}

/// The "static" limit (px) of a refinement round: 2.5 x the median residual in the first
/// (within [tau_min, tau]), so that a poor first estimate, whose static residuals are all a few
/// pixels, still selects the static points; tau_min after.
double staticLimit(int round, std::vector<float> squaredResiduals, const DynamicParameters& params)
{
    if (round > 0)
        return params.tau_min;
    const auto med = static_cast<double>(median(std::move(squaredResiduals)));
    return std::clamp(kFirstRoundMedianFactor * std::sqrt(med), params.tau_min, params.tau);
}

/// Keeps `count` of the pairs, evenly spread.
void keepEvenlySpread(std::vector<cv::Point3f>& object, std::vector<cv::Point2f>& image,
                      size_t count)
{
    if (object.size() <= count)
        return;
    const double step = static_cast<double>(object.size()) / static_cast<double>(count);
    for (size_t k = 0; k < count; ++k)
    {
        const auto source = static_cast<size_t>(static_cast<double>(k) * step);
        object[k] = object[source];
        image[k] = image[source];
    }
    object.resize(count);
    image.resize(count);
}

/// T_prev_cur refined on 3D points of the current frame and their tracked reference pixels.
std::optional<Eigen::Isometry3d> refineOn(const std::vector<cv::Point3f>& object,
                                          std::vector<cv::Point2f> image,
                                          const core::PinholeCamera& camera,
                                          const Eigen::Isometry3d& T_prev_cur)
{
    if (camera.hasDistortion())
        cv::undistortPoints(image, image, camera.cameraMatrix(), camera.distCoeffs(), cv::noArray(),
                            camera.cameraMatrix());
    std::vector<Eigen::Vector3d> points(object.size());
    std::vector<Eigen::Vector2d> pixels(image.size());
    for (size_t k = 0; k < object.size(); ++k)
    {
        points[k] = Eigen::Vector3d(object[k].x, object[k].y, object[k].z);
        pixels[k] = Eigen::Vector2d(image[k].x, image[k].y);
    }
    return refinePose(points, pixels, camera, T_prev_cur);
}

/// Ends of the prediction segments of the keypoints without depth (kUnknownNear..kUnknownFar;
/// for a static point of unknown depth only the epipolar direction is known).
void unknownDepthSegments(const features::FeatureSet& features, const DepthHypotheses& h,
                          const core::PinholeCamera& camera, const Eigen::Isometry3d& T_cur_prev,
                          std::vector<cv::Point2f>& segmentNear,
                          std::vector<cv::Point2f>& segmentFar)
{
    const Eigen::Isometry3d T_prev_cur = T_cur_prev.inverse();
    std::vector<cv::Point3f> nearEnd, farEnd;
    for (size_t i : h.unknown)
    {
        const auto& p = features.undistorted[i];
        for (const double zEnd : {kUnknownNear, kUnknownFar})
        {
            Eigen::Vector3d X = T_prev_cur * camera.unproject(p.x, p.y, zEnd);
            if (X.z() <= kMinReferenceDepth)  // behind the reference camera: the median's point
                X = T_prev_cur *
                    Eigen::Vector3d(h.nearPoint[i].x, h.nearPoint[i].y, h.nearPoint[i].z);
            (zEnd == kUnknownNear ? nearEnd : farEnd).push_back(toCv(X));
        }
    }
    toReferencePixels(camera, nearEnd, segmentNear);
    toReferencePixels(camera, farEnd, segmentFar);
}

float distanceToSegment(const cv::Point2f& p, const cv::Point2f& a, const cv::Point2f& b)
{
    const cv::Point2f ab = b - a;
    const float len2 = ab.dot(ab);
    const float t = len2 > 0.0F ? std::clamp((p - a).dot(ab) / len2, 0.0F, 1.0F) : 0.0F;
    const cv::Point2f d = p - (a + t * ab);
    return std::sqrt(d.dot(d));
}
}  // namespace

DepthHypotheses hypothesiseDepths(const features::FeatureSet& features, const cv::Mat& depth,
                                  const core::PinholeCamera& camera)
{
    const size_t n = features.size();
    DepthHypotheses h;
    h.measured.assign(n, 0.0F);
    std::vector<float> known;
    for (size_t i = 0; i < n; ++i)
        if (!features.depth.empty() && features.depth[i] > 0.0F)
        {
            h.measured[i] = features.depth[i];
            known.push_back(h.measured[i]);
        }
    const float fallbackDepth = known.empty() ? kNoDepthFallback : median(std::move(known));
    // A keypoint without depth usually sits on a depth edge: it belongs to the nearer or the
    // farther surface around it, so both are tried and the better-fitting one decides. Without
    // any depth near, the frame's median starts the flow.
    h.nearPoint.resize(n);
    h.farPoint.resize(n);
    for (size_t i = 0; i < n; ++i)
    {
        float zNear = h.measured[i], zFar = h.measured[i];
        if (zNear <= 0.0F)
        {
            std::tie(zNear, zFar) = depthRangeAround(depth, features.keypoints[i].pt);
            if (zFar <= 0.0F)
            {
                zNear = zFar = fallbackDepth;
                h.unknown.push_back(i);
            }
        }
        const auto& p = features.undistorted[i];
        h.nearPoint[i] = toCv(camera.unproject(p.x, p.y, static_cast<double>(zNear)));
        h.farPoint[i] = toCv(camera.unproject(p.x, p.y, static_cast<double>(zFar)));
    }
    return h;
}

Prediction predictInReference(const DepthHypotheses& hypotheses, const core::PinholeCamera& camera,
                              const Eigen::Isometry3d& T_cur_prev)
{
    Prediction p;
    p.referenceDepth.resize(hypotheses.nearPoint.size());
    const Eigen::Isometry3d T_prev_cur = T_cur_prev.inverse();
    projectIntoReference(camera, T_prev_cur, hypotheses.nearPoint, p.pixels, &p.referenceDepth);
    projectIntoReference(camera, T_prev_cur, hypotheses.farPoint, p.pixelsFar, nullptr);
    return p;
}

FlowTracks trackIntoReference(const std::vector<cv::Mat>& currentPyramid,
                              const std::vector<cv::Mat>& referencePyramid,
                              const features::FeatureSet& features,
                              const std::vector<cv::Point2f>& predicted,
                              const DynamicParameters& params)
{
    FlowTracks t;
    t.tracked = predicted;
    std::vector<cv::Point2f> from;
    for (const auto& kp : features.keypoints)
        from.push_back(kp.pt);
    cv::calcOpticalFlowPyrLK(
        currentPyramid, referencePyramid, from, t.tracked, t.status, t.error,
        cv::Size(params.strong_lk_window, params.strong_lk_window), params.strong_lk_levels,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.03),
        cv::OPTFLOW_USE_INITIAL_FLOW);
    return t;
}

std::vector<bool> refinementCandidates(const DepthHypotheses& hypotheses, const FlowTracks& tracks,
                                       const std::vector<bool>& wasDynamic)
{
    const size_t n = hypotheses.measured.size();
    auto tracked = [&](size_t i) { return tracks.status[i] != 0 && hypotheses.measured[i] > 0.0F; };
    size_t withoutMovers = 0;
    for (size_t i = 0; i < n; ++i)
        withoutMovers += tracked(i) && !wasDynamic[i] ? 1 : 0;
    // Keypoints that were on movers stay out, unless too few others remain.
    const bool useTemporal = withoutMovers >= kMinWithoutMovers;
    std::vector<bool> usable(n);
    for (size_t i = 0; i < n; ++i)
        usable[i] = tracked(i) && !(useTemporal && wasDynamic[i]);
    return usable;
}

void refineEgoMotionOnTracks(const DepthHypotheses& hypotheses, const FlowTracks& tracks,
                             const std::vector<bool>& usable, const core::PinholeCamera& camera,
                             const DynamicParameters& params, Eigen::Isometry3d& T_cur_prev,
                             Prediction& prediction)
{
    const size_t n = usable.size();
    for (int round = 0; round < kRefineRounds; ++round)
    {
        auto candidate = [&](size_t i) {
            return usable[i] &&
                   prediction.referenceDepth[i] > static_cast<float>(kMinReferenceDepth);
        };
        std::vector<float> squared;
        for (size_t i = 0; i < n; ++i)
            if (candidate(i))
            {
                const cv::Point2f d = tracks.tracked[i] - prediction.pixels[i];
                squared.push_back(d.dot(d));
            }
        if (squared.size() < kMinRefineTracks)
            return;
        const double limit = staticLimit(round, std::move(squared), params);
        std::vector<cv::Point3f> object;
        std::vector<cv::Point2f> image;
        for (size_t i = 0; i < n; ++i)
        {
            const cv::Point2f d = tracks.tracked[i] - prediction.pixels[i];
            if (candidate(i) && d.dot(d) < static_cast<float>(limit * limit))
            {
                object.push_back(hypotheses.nearPoint[i]);
                image.push_back(tracks.tracked[i]);
            }
        }
        if (object.size() < kMinRefineTracks)
            return;
        keepEvenlySpread(object, image, kMaxRefineTracks);
        const auto T_prev_cur = refineOn(object, image, camera, T_cur_prev.inverse());
        if (!T_prev_cur)
            return;
        T_cur_prev = T_prev_cur->inverse();
        prediction = predictInReference(hypotheses, camera, T_cur_prev);
    }
}

void measureEvidence(const features::FeatureSet& features, const DepthHypotheses& hypotheses,
                     const Prediction& prediction, const FlowTracks& tracks,
                     const cv::Mat& referenceDepth, const core::PinholeCamera& camera,
                     const Eigen::Isometry3d& T_cur_prev, const DynamicParameters& params,
                     std::vector<KeypointEvidence>& evidence)
{
    std::vector<cv::Point2f> segmentNear, segmentFar;
    unknownDepthSegments(features, hypotheses, camera, T_cur_prev, segmentNear, segmentFar);
    std::vector<int> unknownSlot(evidence.size(), -1);
    for (size_t k = 0; k < hypotheses.unknown.size(); ++k)
        unknownSlot[hypotheses.unknown[k]] = static_cast<int>(k);

    const int w = referenceDepth.cols, h = referenceDepth.rows;
    for (size_t i = 0; i < evidence.size(); ++i)
    {
        const cv::Point2f& q = prediction.pixels[i];
        if (q.x < 0.0F || q.y < 0.0F || q.x > static_cast<float>(w - 1) ||
            q.y > static_cast<float>(h - 1))
            continue;  // was outside the previous view: no evidence
        auto& e = evidence[i];
        // Depth: the point now sits where the reference frame saw farther through (something
        // moved in front). Only with a measured depth. And the reverse: where the reference
        // saw something much closer (farther than a person moves in frame_gap_s), the
        // point was hidden then and is revealed now; its flow says nothing.
        bool hidden = false;
        const float zRef = prediction.referenceDepth[i];
        if (hypotheses.measured[i] > 0.0F)
        {
            const float zp = referenceDepth.at<float>(static_cast<int>(std::lround(q.y)),
                                                      static_cast<int>(std::lround(q.x)));
            const double margin = std::max(params.depth_margin, params.depth_ratio * zp);
            e.depth = zp > 0.0F && zRef < zp - margin;
            hidden = zp > 0.0F && zp < zRef - std::max(params.occlusion_margin, margin);
        }
        if (tracks.status[i] == 0 || hidden)
            continue;
        e.patchError = tracks.error[i];
        const cv::Point2f d = tracks.tracked[i] - q;
        const cv::Point2f dFar = tracks.tracked[i] - prediction.pixelsFar[i];
        e.residual = std::sqrt(std::min(d.dot(d), dFar.dot(dFar)));
        if (unknownSlot[i] >= 0)
        {
            const auto k = static_cast<size_t>(unknownSlot[i]);
            e.residual = std::min(
                e.residual, distanceToSegment(tracks.tracked[i], segmentNear[k], segmentFar[k]));
        }
    }
}

std::optional<double> adaptiveTau(const std::vector<KeypointEvidence>& evidence,
                                  const DynamicParameters& params)
{
    // Most keypoints are static, so the median and MAD of the residuals describe how well the
    // ego-motion compensates this frame. Where movers fill much of the view, the keypoints that
    // were static describe it better than all of them.
    std::vector<float> r, rBefore;
    for (const auto& e : evidence)
    {
        if (e.residual < 0.0F)
            continue;
        r.push_back(e.residual);
        if (!e.wasDynamic)
            rBefore.push_back(e.residual);
    }
    if (rBefore.size() >= kMinWithoutMovers)
        r.swap(rBefore);
    if (r.size() < kMinResidualsForTau)
        return std::nullopt;
    const auto med = static_cast<double>(median(r));
    std::vector<float> dev;
    dev.reserve(r.size());
    for (float x : r)
        dev.push_back(std::abs(x - static_cast<float>(med)));
    const double sigma = kMadToSigma * static_cast<double>(median(std::move(dev)));
    return std::clamp(med + params.tau_sigmas * sigma, params.tau_min, params.tau);
}

NeighbourCounter::NeighbourCounter(const features::FeatureSet& features,
                                   const DynamicParameters& params)
    : features_(features), params_(params)
{
    for (const auto& kp : features.keypoints)
    {
        width_ = std::max(width_, static_cast<int>(kp.pt.x) + 1);
        height_ = std::max(height_, static_cast<int>(kp.pt.y) + 1);
        points_.push_back(kp.pt);
    }
    constexpr int kGridCell = 32;
    grid_ = features::FeatureGrid(points_, std::vector<int>(features.size(), 0), width_, height_,
                                  kGridCell);
}

std::pair<int, int> NeighbourCounter::count(size_t i, const std::vector<bool>& flags) const
{
    const float zi = features_.depth[i];
    int near = 0, flagged = 0;
    for (size_t j :
         grid_.query(points_[i].x, points_[i].y, static_cast<float>(params_.region_radius)))
    {
        if (j != i && features_.depth[j] > 0.0F &&
            std::abs(features_.depth[j] - zi) <= params_.region_depth)
        {
            near++;
            flagged += flags[j] ? 1 : 0;
        }
    }
    return {near, flagged};
}

void overruleIsolatedFlow(const features::FeatureSet& features, const NeighbourCounter& neighbours,
                          const DynamicParameters& params, std::vector<KeypointEvidence>& evidence)
{
    // People carry many keypoints that move together: flow evidence alone among mostly static
    // depth-similar neighbours (at most isolated_fraction of at least region_min_neighbours) is
    // noise. Decided on the flags before any change.
    std::vector<bool> was(evidence.size());
    for (size_t i = 0; i < evidence.size(); ++i)
        was[i] = evidence[i].dynamic;
    for (size_t i = 0; i < evidence.size(); ++i)
    {
        auto& e = evidence[i];
        if (!e.flow || e.depth || features.depth[i] <= 0.0F)
            continue;
        const auto [near, dyn] = neighbours.count(i, was);
        if (near >= params.region_min_neighbours && dyn <= params.isolated_fraction * near)
        {
            e.isolated = true;
            e.dynamic = false;
        }
    }
}

void growDynamicRegions(const features::FeatureSet& features, const NeighbourCounter& neighbours,
                        const DynamicParameters& params, std::vector<KeypointEvidence>& evidence)
{
    // Dynamic keypoints per coarse cell (region_radius wide): a keypoint with no dynamic one in
    // its 3x3 cells cannot flip, and skips the neighbour query.
    const double cell = params.region_radius;
    const int cols = static_cast<int>(neighbours.width() / cell) + 1;
    const int rows = static_cast<int>(neighbours.height() / cell) + 1;
    auto cellIndex = [&](int x, int y)
    { return static_cast<size_t>(y) * static_cast<size_t>(cols) + static_cast<size_t>(x); };
    auto cellOf = [&](const cv::Point2f& p)
    { return std::make_pair(static_cast<int>(p.x / cell), static_cast<int>(p.y / cell)); };
    constexpr int kSweeps = 2;
    for (int sweep = 0; sweep < kSweeps; ++sweep)
    {
        std::vector<bool> was(evidence.size());
        std::vector<int> dynamicInCell(static_cast<size_t>(cols * rows), 0);
        for (size_t i = 0; i < evidence.size(); ++i)
        {
            was[i] = evidence[i].dynamic;
            if (was[i])
            {
                const auto [cx, cy] = cellOf(neighbours.point(i));
                dynamicInCell[cellIndex(cx, cy)]++;
            }
        }
        for (size_t i = 0; i < evidence.size(); ++i)
        {
            const float zi = features.depth.empty() ? 0.0F : features.depth[i];
            if (was[i] || zi <= 0.0F)
                continue;
            const auto [cx, cy] = cellOf(neighbours.point(i));
            int around = 0;
            for (int y = std::max(0, cy - 1); y <= std::min(rows - 1, cy + 1); ++y)
                for (int x = std::max(0, cx - 1); x <= std::min(cols - 1, cx + 1); ++x)
                    around += dynamicInCell[cellIndex(x, y)];
            if (around == 0)
                continue;
            const auto [near, dyn] = neighbours.count(i, was);
            if (near >= params.region_min_neighbours && 2 * dyn > near)
            {
                evidence[i].region = true;
                evidence[i].dynamic = true;
            }
        }
    }
}
}  // namespace smap::dynamic::strong
