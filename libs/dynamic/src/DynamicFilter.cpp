#include "smap/dynamic/DynamicFilter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "smap/dynamic/FrameWarp.h"
#include "smap/features/FeatureGrid.h"

namespace smap::dynamic
{
std::vector<float> DynamicResult::weights() const
{
    std::vector<float> w(keypoints.size(), evaluated ? 1.0F : 0.0F);
    for (size_t i = 0; i < keypoints.size(); ++i)
        if (keypoints[i].dynamic)
            w[i] = 0.0F;
    return w;
}

std::vector<bool> DynamicResult::mappable() const
{
    const bool measured = std::any_of(keypoints.begin(), keypoints.end(),
                                      [](const KeypointEvidence& k) { return k.residual >= 0.0F; });
    if (!measured)
        return {};
    std::vector<bool> m(keypoints.size());
    for (size_t i = 0; i < keypoints.size(); ++i)
        m[i] = !keypoints[i].dynamic && keypoints[i].residual >= 0.0F;
    return m;
}

size_t DynamicResult::numDynamic() const
{
    size_t n = 0;
    for (const auto& k : keypoints)
        n += k.dynamic ? 1 : 0;
    return n;
}

namespace
{
/// Depth range (m) a keypoint without any depth near it may have.
constexpr double kUnknownNear = 0.3;
constexpr double kUnknownFar = 100.0;

float distanceToSegment(const cv::Point2f& p, const cv::Point2f& a, const cv::Point2f& b)
{
    const cv::Point2f ab = b - a;
    const float len2 = ab.dot(ab);
    const float t = len2 > 0.0F ? std::clamp((p - a).dot(ab) / len2, 0.0F, 1.0F) : 0.0F;
    const cv::Point2f d = p - (a + t * ab);
    return std::sqrt(d.dot(d));
}
}  // namespace

DynamicFilter::DynamicFilter(const DynamicParameters& params) : params_(params) {}

DynamicResult DynamicFilter::process(const cv::Mat& colour, const cv::Mat& depth,
                                     const features::FeatureSet& features,
                                     const core::PinholeCamera& camera)
{
    const auto t0 = std::chrono::steady_clock::now();
    DynamicResult result;
    result.keypoints.resize(features.size());
    result.tau = params_.tau;
    cv::Mat grey;
    if (colour.channels() == 3)
        cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
    else
        grey = colour.clone();

    auto lap = std::chrono::steady_clock::now();
    const Stopwatch msSinceLap = [&lap]()
    {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - lap).count();
        lap = now;
        return ms;
    };
    const bool strong = params_.mode == FilterMode::Strong;
    if (strong)
    {
        // The current pyramid is also the next frame's previous one.
        cv::buildOpticalFlowPyramid(grey, currentPyramid_,
                                    cv::Size(params_.strong_lk_window, params_.strong_lk_window),
                                    params_.strong_lk_levels, true);
        result.warpMilliseconds = msSinceLap();
    }
    result.evaluated = params_.mode == FilterMode::Off || !history_.empty();
    if (params_.mode != FilterMode::Off && !history_.empty() && features.size() > 0)
    {
        result.framesBack = history_.size();
        if (strong)
            processStrong(depth, features, camera, msSinceLap, result);
        else
            processPaper(grey, features, camera, msSinceLap, result);
    }
    if (strong && result.framesBack > 0 && result.egoMotion.valid)
    {
        lastMotion_ = result.egoMotion.T_cur_prev;
        lastFramesBack_ = result.framesBack;
    }
    else
    {
        lastMotion_.reset();
    }
    if (params_.mode != FilterMode::Off)
    {
        PastFrame past;
        past.grey = grey;
        past.pyramid = std::move(currentPyramid_);
        currentPyramid_.clear();
        past.depth = depth;
        past.features = features;
        if (result.evaluated && strong)
        {
            past.dynamic.resize(result.keypoints.size());
            for (size_t i = 0; i < result.keypoints.size(); ++i)
                past.dynamic[i] = result.keypoints[i].dynamic;
            past.cells = DecisionCells::count(features, past.dynamic, depth.cols, depth.rows);
        }
        history_.push_back(std::move(past));
        const size_t keep = strong ? static_cast<size_t>(params_.frame_gap) : 1;
        while (history_.size() > keep)
            history_.pop_front();
    }
    result.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
}
void DynamicFilter::processPaper(const cv::Mat& grey, const features::FeatureSet& features,
                                 const core::PinholeCamera& camera, const Stopwatch& lap,
                                 DynamicResult& result) const
{
    result.egoMotion = estimateEgoMotionFivePoint(reference().features, features, camera, params_);
    result.egoMotionMilliseconds = lap();
    if (!result.egoMotion.valid)
        return;
    const WarpedFrame warped = warpIntoCurrentView(reference().grey, reference().depth, camera,
                                                   result.egoMotion.T_cur_prev);
    result.warpMilliseconds = lap();
    // Flow from the warped previous frame to the current one, started at the current
    // keypoints (distorted pixels: both images are on the distorted grid).
    std::vector<cv::Point2f> from, to;
    for (const auto& kp : features.keypoints)
        from.push_back(kp.pt);
    std::vector<uint8_t> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(
        warped.grey, grey, from, to, status, err, cv::Size(params_.lk_window, params_.lk_window),
        params_.lk_levels,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01));
    result.flowMilliseconds = lap();
    for (size_t i = 0; i < from.size(); ++i)
    {
        if (status[i] == 0)
            continue;
        const cv::Point2f d = to[i] - from[i];
        auto& e = result.keypoints[i];
        e.residual = std::sqrt(d.x * d.x + d.y * d.y);
        e.flow = e.residual > params_.tau;
        e.dynamic = e.flow;
    }
}

void DynamicFilter::processStrong(const cv::Mat& depth, const features::FeatureSet& features,
                                  const core::PinholeCamera& camera, const Stopwatch& lap,
                                  DynamicResult& result) const
{
    // No final iterative refinement: the flow tracks refine the pose below. The prior competing
    // with RANSAC is the last ego-motion over the same gap or, on the first comparison of a
    // sequence, a camera at rest: without it the first frames have no defence against people
    // who outvote the background (RANSAC then locks onto them, and the next frames' priors
    // with it).
    std::optional<Eigen::Isometry3d> prior;
    if (lastMotion_ && lastFramesBack_ == history_.size())
        prior = lastMotion_;
    else if (!lastMotion_ && history_.size() == 1)
        prior = Eigen::Isometry3d::Identity();
    result.egoMotion = estimateEgoMotionDepthPnp(reference().features, features, camera, params_,
                                                 false, reference().dynamic, prior);
    if (!result.egoMotion.valid)
        result.egoMotion =
            estimateEgoMotionFivePoint(reference().features, features, camera, params_);
    result.egoMotionMilliseconds = lap();
    if (!result.egoMotion.valid)
        return;
    // Instead of warping the whole previous image, predict where each current keypoint was in
    // the previous frame (its depth and the ego-motion; the frame's median depth where it has
    // none), then let Lucas-Kanade find where it really was, starting from the prediction: a
    // static point is found at the prediction, a mover away from it. Same residual as the
    // warp's, at a fraction of the cost.
    const size_t n = features.size();
    std::vector<float> z(n, 0.0F);
    std::vector<float> known;
    for (size_t i = 0; i < n; ++i)
        if (!features.depth.empty() && features.depth[i] > 0.0F)
        {
            z[i] = features.depth[i];
            known.push_back(z[i]);
        }
    float fallbackDepth = 2.0F;
    if (!known.empty())
    {
        std::nth_element(known.begin(), known.begin() + static_cast<long>(known.size() / 2),
                         known.end());
        fallbackDepth = known[known.size() / 2];
    }
    // A keypoint without depth usually sits on a depth edge: it belongs to the nearer or the
    // farther surface around it, so both are tried (the nearest and farthest valid depth within
    // 4 px) and the better-fitting one decides. Without any depth near, the frame's median
    // starts the flow, and the residual is the distance to the whole segment of predictions
    // for depths kUnknownNear..kUnknownFar (for a static point of unknown depth only the
    // epipolar direction is known).
    std::vector<cv::Point3f> X_cur(n), X_alt(n);
    std::vector<size_t> unknownDepth;
    for (size_t i = 0; i < n; ++i)
    {
        float zNear = z[i], zFar = z[i];
        if (zNear <= 0.0F)
        {
            zNear = std::numeric_limits<float>::max();
            zFar = 0.0F;
            const int u0 = cvRound(features.keypoints[i].pt.x);
            const int v0 = cvRound(features.keypoints[i].pt.y);
            for (int v = std::max(0, v0 - 4); v <= std::min(depth.rows - 1, v0 + 4); ++v)
            {
                for (int u = std::max(0, u0 - 4); u <= std::min(depth.cols - 1, u0 + 4); ++u)
                {
                    const float d = depth.at<float>(v, u);
                    if (d > 0.0F)
                    {
                        zNear = std::min(zNear, d);
                        zFar = std::max(zFar, d);
                    }
                }
            }
            if (zFar <= 0.0F)
            {
                zNear = zFar = fallbackDepth;
                unknownDepth.push_back(i);
            }
        }
        const auto& p = features.undistorted[i];
        auto toCv = [](const Eigen::Vector3d& X)
        {
            return cv::Point3f(static_cast<float>(X.x()), static_cast<float>(X.y()),
                               static_cast<float>(X.z()));
        };
        X_cur[i] = toCv(camera.unproject(p.x, p.y, static_cast<double>(zNear)));
        X_alt[i] = toCv(camera.unproject(p.x, p.y, static_cast<double>(zFar)));
    }
    // Where the keypoints were in the reference image (distorted pixels) under an ego-motion,
    // and their depth there; `predictedAlt` under the farther depth hypothesis.
    std::vector<cv::Point2f> predicted, predictedAlt;
    std::vector<float> zPrevious(n);
    // Points in the reference camera's frame to its (distorted) pixels.
    auto toPixels = [&camera](const std::vector<cv::Point3f>& points, std::vector<cv::Point2f>& out)
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
    };
    auto project = [&](const Eigen::Isometry3d& T_prev_cur, const std::vector<cv::Point3f>& Xs,
                       std::vector<cv::Point2f>& out, bool keepDepth)
    {
        std::vector<cv::Point3f> inPrevious(n);
        for (size_t i = 0; i < n; ++i)
        {
            const Eigen::Vector3d X = T_prev_cur * Eigen::Vector3d(Xs[i].x, Xs[i].y, Xs[i].z);
            if (keepDepth)
                zPrevious[i] = static_cast<float>(X.z());
            // Behind the reference camera: projected far outside, so it gets no evidence.
            inPrevious[i] = X.z() > 0.05
                                ? cv::Point3f(static_cast<float>(X.x()), static_cast<float>(X.y()),
                                              static_cast<float>(X.z()))
                                : cv::Point3f(1e4F, 1e4F, 1.0F);
        }
        toPixels(inPrevious, out);
    };
    auto predict = [&](const Eigen::Isometry3d& T_cur_prev)
    {
        const Eigen::Isometry3d T_prev_cur = T_cur_prev.inverse();
        project(T_prev_cur, X_cur, predicted, true);
        project(T_prev_cur, X_alt, predictedAlt, false);
    };
    predict(result.egoMotion.T_cur_prev);
    std::vector<cv::Point2f> from, tracked = predicted;
    for (const auto& kp : features.keypoints)
        from.push_back(kp.pt);
    std::vector<uint8_t> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(
        currentPyramid_, reference().pyramid, from, tracked, status, err,
        cv::Size(params_.strong_lk_window, params_.strong_lk_window), params_.strong_lk_levels,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.03),
        cv::OPTFLOW_USE_INITIAL_FLOW);
    result.flowMilliseconds = lap();
    const std::vector<bool> wasDynamic = dynamicBefore(status, tracked, predicted);
    size_t candidates = 0;
    for (size_t i = 0; i < n; ++i)
    {
        result.keypoints[i].wasDynamic = wasDynamic[i];
        candidates += status[i] != 0 && z[i] > 0.0F && !wasDynamic[i] ? 1 : 0;
    }
    // Keypoints that were on movers stay out of the refinement, unless too few others remain.
    const bool useTemporal = candidates >= 40;
    auto refineCandidate = [&](size_t i)
    {
        return status[i] != 0 && z[i] > 0.0F && zPrevious[i] > 0.05F &&
               !(useTemporal && wasDynamic[i]);
    };

    // Refine the ego-motion on the sub-pixel Lucas-Kanade tracks of the keypoints with depth
    // that look static under the current estimate: several hundred correspondences, more
    // precise than the descriptor matches it started from. The tracks themselves do not depend
    // on the pose, so no second flow pass is needed. Three rounds; "static" is a residual
    // below tau_min, in the first round below 2.5 x the median residual (within [tau_min,
    // tau]), so a poor first estimate (whose static residuals are all a few pixels) still
    // selects the static points.
    for (int round = 0; round < 3; ++round)
    {
        std::vector<float> sq;
        for (size_t i = 0; i < n; ++i)
            if (refineCandidate(i))
            {
                const cv::Point2f d = tracked[i] - predicted[i];
                sq.push_back(d.dot(d));
            }
        if (sq.size() < 20)
            break;
        std::nth_element(sq.begin(), sq.begin() + static_cast<long>(sq.size() / 2), sq.end());
        const double limit =
            round == 0 ? std::clamp(2.5 * std::sqrt(static_cast<double>(sq[sq.size() / 2])),
                                    params_.tau_min, params_.tau)
                       : params_.tau_min;
        std::vector<cv::Point3f> object;
        std::vector<cv::Point2f> image;
        for (size_t i = 0; i < n; ++i)
        {
            const cv::Point2f d = tracked[i] - predicted[i];
            if (refineCandidate(i) && d.dot(d) < static_cast<float>(limit * limit))
            {
                object.push_back(X_cur[i]);
                image.push_back(tracked[i]);
            }
        }
        if (object.size() < 20)
            break;
        // A few hundred sub-pixel tracks fix the pose; more only cost time.
        constexpr size_t kMaxRefinePoints = 200;
        if (object.size() > kMaxRefinePoints)
        {
            const double step = static_cast<double>(object.size()) / kMaxRefinePoints;
            for (size_t k = 0; k < kMaxRefinePoints; ++k)
            {
                const auto source = static_cast<size_t>(static_cast<double>(k) * step);
                object[k] = object[source];
                image[k] = image[source];
            }
            object.resize(kMaxRefinePoints);
            image.resize(kMaxRefinePoints);
        }
        if (camera.hasDistortion())
            cv::undistortPoints(image, image, camera.cameraMatrix(), camera.distCoeffs(),
                                cv::noArray(), camera.cameraMatrix());
        std::vector<Eigen::Vector3d> points(object.size());
        std::vector<Eigen::Vector2d> pixels(image.size());
        for (size_t k = 0; k < object.size(); ++k)
        {
            points[k] = Eigen::Vector3d(object[k].x, object[k].y, object[k].z);
            pixels[k] = Eigen::Vector2d(image[k].x, image[k].y);
        }
        const auto T_prev_cur =
            refinePose(points, pixels, camera, result.egoMotion.T_cur_prev.inverse());
        if (!T_prev_cur)
            break;
        result.egoMotion.T_cur_prev = T_prev_cur->inverse();
        predict(result.egoMotion.T_cur_prev);
    }

    // The ends of the unknown-depth keypoints' prediction segments.
    std::vector<cv::Point2f> segmentNear, segmentFar;
    {
        const Eigen::Isometry3d T_prev_cur = result.egoMotion.T_cur_prev.inverse();
        std::vector<cv::Point3f> nearEnd, farEnd;
        for (size_t i : unknownDepth)
        {
            const auto& p = features.undistorted[i];
            for (const double zEnd : {kUnknownNear, kUnknownFar})
            {
                Eigen::Vector3d X = T_prev_cur * camera.unproject(p.x, p.y, zEnd);
                if (X.z() <= 0.05)  // behind the reference camera: the median depth's point
                    X = T_prev_cur * Eigen::Vector3d(X_cur[i].x, X_cur[i].y, X_cur[i].z);
                (zEnd == kUnknownNear ? nearEnd : farEnd)
                    .emplace_back(static_cast<float>(X.x()), static_cast<float>(X.y()),
                                  static_cast<float>(X.z()));
            }
        }
        toPixels(nearEnd, segmentNear);
        toPixels(farEnd, segmentFar);
    }
    std::vector<int> unknownSlot(n, -1);
    for (size_t k = 0; k < unknownDepth.size(); ++k)
        unknownSlot[unknownDepth[k]] = static_cast<int>(k);

    const int w = reference().depth.cols, h = reference().depth.rows;
    for (size_t i = 0; i < n; ++i)
    {
        const cv::Point2f& q = predicted[i];
        if (q.x < 0.0F || q.y < 0.0F || q.x > static_cast<float>(w - 1) ||
            q.y > static_cast<float>(h - 1))
            continue;  // was outside the previous view: no evidence
        auto& e = result.keypoints[i];
        // Depth: the point now sits where the reference frame saw farther through (something
        // moved in front). Only with a measured depth. And the reverse: where the reference
        // saw something much closer (farther than a person moves in frame_gap frames), the
        // point was hidden then and is revealed now; its flow says nothing.
        bool hidden = false;
        if (z[i] > 0.0F)
        {
            const float zp = reference().depth.at<float>(static_cast<int>(std::lround(q.y)),
                                                         static_cast<int>(std::lround(q.x)));
            const double margin = std::max(params_.depth_margin, params_.depth_ratio * zp);
            e.depth = zp > 0.0F && zPrevious[i] < zp - margin;
            hidden = zp > 0.0F && zp < zPrevious[i] - std::max(params_.occlusion_margin, margin);
        }
        if (status[i] != 0 && !hidden)
        {
            e.patchError = err[i];
            const cv::Point2f d = tracked[i] - q, dAlt = tracked[i] - predictedAlt[i];
            e.residual = std::sqrt(std::min(d.dot(d), dAlt.dot(dAlt)));
            if (unknownSlot[i] >= 0)
            {
                const auto k = static_cast<size_t>(unknownSlot[i]);
                e.residual = std::min(e.residual,
                                      distanceToSegment(tracked[i], segmentNear[k], segmentFar[k]));
            }
        }
    }
    decideStrong(features, result);
}

std::vector<bool> DynamicFilter::dynamicBefore(const std::vector<uint8_t>& status,
                                               const std::vector<cv::Point2f>& tracked,
                                               const std::vector<cv::Point2f>& predicted) const
{
    std::vector<bool> out(tracked.size(), false);
    const DecisionCells& cells = reference().cells;
    if (cells.all.empty())
        return out;
    for (size_t i = 0; i < tracked.size(); ++i)
    {
        const cv::Point2f& q = status[i] != 0 ? tracked[i] : predicted[i];
        const int cx = static_cast<int>(std::floor(q.x / DecisionCells::kCell));
        const int cy = static_cast<int>(std::floor(q.y / DecisionCells::kCell));
        const auto [all, dyn] = cells.around(cx, cy, 1);
        out[i] = 2 * dyn > all;
    }
    return out;
}

cv::Mat DynamicFilter::moverRegions() const
{
    if (params_.mode != FilterMode::Strong || history_.empty())
        return {};
    const PastFrame& last = history_.back();
    const DecisionCells& c = last.cells;
    if (c.all.empty() || last.dynamic.empty())
        return {};
    const auto dynamicKeypoints = std::count(last.dynamic.begin(), last.dynamic.end(), true);
    if (static_cast<double>(dynamicKeypoints) <=
        params_.extraction_priority_above * static_cast<double>(last.dynamic.size()))
        return {};
    // 5 x 5 cells (40 px): a 3 x 3 block holds about two keypoints, too few to cover a person.
    constexpr int kRadius = 2;
    cv::Mat mask(c.rows, c.cols, CV_8UC1, cv::Scalar(0));
    bool any = false;
    for (int y = 0; y < c.rows; ++y)
    {
        for (int x = 0; x < c.cols; ++x)
        {
            const auto [all, dynamic] = c.around(x, y, kRadius);
            if (dynamic >= 2 && 2 * dynamic > all)
            {
                mask.at<uint8_t>(y, x) = 255;
                any = true;
            }
        }
    }
    return any ? mask : cv::Mat();
}

std::pair<int, int> DynamicFilter::DecisionCells::around(int cx, int cy, int radius) const
{
    int n = 0, nDynamic = 0;
    for (int y = std::max(0, cy - radius); y <= std::min(rows - 1, cy + radius); ++y)
    {
        for (int x = std::max(0, cx - radius); x <= std::min(cols - 1, cx + radius); ++x)
        {
            const size_t k =
                static_cast<size_t>(y) * static_cast<size_t>(cols) + static_cast<size_t>(x);
            n += all[k];
            nDynamic += dynamic[k];
        }
    }
    return {n, nDynamic};
}

DynamicFilter::DecisionCells DynamicFilter::DecisionCells::count(
    const features::FeatureSet& features, const std::vector<bool>& dynamic, int width, int height)
{
    DecisionCells c;
    c.cols = (width + kCell - 1) / kCell;
    c.rows = (height + kCell - 1) / kCell;
    c.all.assign(static_cast<size_t>(c.cols) * static_cast<size_t>(c.rows), 0);
    c.dynamic.assign(c.all.size(), 0);
    for (size_t i = 0; i < features.size() && i < dynamic.size(); ++i)
    {
        const int x =
            std::clamp(static_cast<int>(features.keypoints[i].pt.x) / kCell, 0, c.cols - 1);
        const int y =
            std::clamp(static_cast<int>(features.keypoints[i].pt.y) / kCell, 0, c.rows - 1);
        const auto k =
            static_cast<size_t>(y) * static_cast<size_t>(c.cols) + static_cast<size_t>(x);
        c.all[k]++;
        c.dynamic[k] += dynamic[i] ? 1 : 0;
    }
    return c;
}

void DynamicFilter::decideStrong(const features::FeatureSet& features, DynamicResult& result) const
{
    auto& kps = result.keypoints;
    // Adaptive tau from the frame's residual statistics: most keypoints are static, so the
    // median and MAD describe how well the ego-motion compensates this frame.
    std::vector<float> r, rBefore;
    for (const auto& e : kps)
    {
        if (e.residual < 0.0F)
            continue;
        r.push_back(e.residual);
        if (!e.wasDynamic)
            rBefore.push_back(e.residual);
    }
    // Where movers fill much of the view, the keypoints that were static describe the
    // compensation better than all of them.
    if (rBefore.size() >= 40)
        r.swap(rBefore);
    if (r.size() < 10)
    {
        for (auto& e : kps)
            e.dynamic = e.depth;
        return;
    }
    auto median = [](std::vector<float> v)
    {
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return static_cast<double>(v[v.size() / 2]);
    };
    const double med = median(r);
    std::vector<float> dev;
    dev.reserve(r.size());
    for (float x : r)
        dev.push_back(std::abs(x - static_cast<float>(med)));
    const double sigma = 1.4826 * median(dev);
    result.tau = std::clamp(med + params_.tau_sigmas * sigma, params_.tau_min, params_.tau);

    for (size_t i = 0; i < kps.size(); ++i)
    {
        auto& e = kps[i];
        e.flow = e.residual >= 0.0F && e.residual > result.tau;
        e.dynamic = e.flow || e.depth;
    }
    // Then region growing over depth-connected neighbours (two Jacobi sweeps, deterministic).
    if (params_.region_radius <= 0.0)
        return;
    std::vector<int> levels(features.size(), 0);
    int maxX = 1, maxY = 1;
    for (const auto& kp : features.keypoints)
    {
        maxX = std::max(maxX, static_cast<int>(kp.pt.x) + 1);
        maxY = std::max(maxY, static_cast<int>(kp.pt.y) + 1);
    }
    std::vector<cv::Point2f> pts;
    for (const auto& kp : features.keypoints)
        pts.push_back(kp.pt);
    const features::FeatureGrid grid(pts, levels, maxX, maxY, 32);
    // Depth-similar neighbours of keypoint i (with depth) within region_radius: how many, and
    // how many of them are flagged in `flags`.
    auto countNeighbours = [&](size_t i, const std::vector<bool>& flags)
    {
        const float zi = features.depth[i];
        int near = 0, flagged = 0;
        for (size_t j : grid.query(pts[i].x, pts[i].y, static_cast<float>(params_.region_radius)))
        {
            if (j != i && features.depth[j] > 0.0F &&
                std::abs(features.depth[j] - zi) <= params_.region_depth)
            {
                near++;
                flagged += flags[j] ? 1 : 0;
            }
        }
        return std::make_pair(near, flagged);
    };
    // Isolated flow evidence: people carry many keypoints that move together, so a keypoint
    // flagged by its flow alone whose depth-similar neighbours are mostly static (at most
    // isolated_fraction of at least region_min_neighbours) is noise (a Lucas-Kanade slip on
    // weak texture) and stays static. Decided on the flags before any change.
    if (params_.isolated_fraction > 0.0 && !features.depth.empty())
    {
        std::vector<bool> was(kps.size());
        for (size_t i = 0; i < kps.size(); ++i)
            was[i] = kps[i].dynamic;
        for (size_t i = 0; i < kps.size(); ++i)
        {
            auto& e = kps[i];
            if (!e.flow || e.depth || features.depth[i] <= 0.0F)
                continue;
            const auto [near, dyn] = countNeighbours(i, was);
            if (near >= params_.region_min_neighbours && dyn <= params_.isolated_fraction * near)
            {
                e.isolated = true;
                e.dynamic = false;
            }
        }
    }
    // Dynamic keypoints per coarse cell (region_radius wide): a keypoint with no dynamic one
    // in its 3x3 cells cannot flip, and skips the neighbour query.
    const double cell = params_.region_radius;
    const int cols = static_cast<int>(maxX / cell) + 1, rows = static_cast<int>(maxY / cell) + 1;
    auto cellOf = [&](const cv::Point2f& p)
    { return std::make_pair(static_cast<int>(p.x / cell), static_cast<int>(p.y / cell)); };
    for (int sweep = 0; sweep < 2; ++sweep)
    {
        std::vector<bool> was(kps.size());
        std::vector<int> dynamicInCell(static_cast<size_t>(cols * rows), 0);
        for (size_t i = 0; i < kps.size(); ++i)
        {
            was[i] = kps[i].dynamic;
            if (was[i])
            {
                const auto [cx, cy] = cellOf(pts[i]);
                dynamicInCell[static_cast<size_t>(cy) * static_cast<size_t>(cols) +
                              static_cast<size_t>(cx)]++;
            }
        }
        for (size_t i = 0; i < kps.size(); ++i)
        {
            const float zi = features.depth.empty() ? 0.0F : features.depth[i];
            if (was[i] || zi <= 0.0F)
                continue;
            const auto [cx, cy] = cellOf(pts[i]);
            int around = 0;
            for (int y = std::max(0, cy - 1); y <= std::min(rows - 1, cy + 1); ++y)
                for (int x = std::max(0, cx - 1); x <= std::min(cols - 1, cx + 1); ++x)
                    around += dynamicInCell[static_cast<size_t>(y) * static_cast<size_t>(cols) +
                                            static_cast<size_t>(x)];
            if (around == 0)
                continue;
            const auto [near, dyn] = countNeighbours(i, was);
            if (near >= params_.region_min_neighbours && 2 * dyn > near)
            {
                kps[i].region = true;
                kps[i].dynamic = true;
            }
        }
    }
}
}  // namespace smap::dynamic
