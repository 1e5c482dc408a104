#include "smap/dynamic/MovableLabelTracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "smap/core/RecordingTime.h"

namespace smap::dynamic
{
namespace
{
constexpr int kCell = 8;

using Label = MovableLabelTracker::Label;
using Motion = MovableLabelTracker::Motion;

/// Labelled keypoints of a cell (or of 3 x 3 cells): how many, how many movable.
struct LabelCount
{
    int known = 0, movable = 0;

    LabelCount& operator+=(const LabelCount& o)
    {
        known += o.known;
        movable += o.movable;
        return *this;
    }
};

/// Per 8 px cell of a frame: its labelled keypoints, all and those the flow test found still,
/// and the nearest movable keypoint's depth.
struct LabelCells
{
    int cols = 0, rows = 0;
    std::vector<LabelCount> all, still;
    std::vector<float> nearest;  ///< nearest movable keypoint (m)

    size_t index(int cx, int cy) const
    {
        return static_cast<size_t>(cy) * static_cast<size_t>(cols) + static_cast<size_t>(cx);
    }

    explicit LabelCells(const MovableLabelTracker::FrameTracks& t, const std::vector<Label>& labels)
    {
        for (const auto& p : t.keypoints)
        {
            cols = std::max(cols, static_cast<int>(p.x) / kCell + 1);
            rows = std::max(rows, static_cast<int>(p.y) / kCell + 1);
        }
        all.assign(static_cast<size_t>(cols) * static_cast<size_t>(rows), LabelCount{});
        still = all;
        nearest.assign(all.size(), std::numeric_limits<float>::max());
        for (size_t i = 0; i < t.keypoints.size(); ++i)
            add(t, labels, i);
    }

    void add(const MovableLabelTracker::FrameTracks& t, const std::vector<Label>& labels, size_t i)
    {
        const cv::Point2f& p = t.keypoints[i];
        if (labels[i] == Label::Unknown || !(p.x >= 0.0F) || !(p.y >= 0.0F))
            return;
        const size_t c = index(static_cast<int>(p.x) / kCell, static_cast<int>(p.y) / kCell);
        const LabelCount one{1, labels[i] == Label::Movable ? 1 : 0};
        all[c] += one;
        if (i < t.motion.size() && t.motion[i] == Motion::Still)
            still[c] += one;
        if (one.movable != 0 && i < t.depth.size() && t.depth[i] > 0.0F)
            nearest[c] = std::min(nearest[c], t.depth[i]);
    }

    /// The label a keypoint takes whose track reaches pixel p, at depth z (<= 0: unknown),
    /// moving or not: the majority of the 3 x 3 cells around p. A still keypoint counts only
    /// the keypoints there that were still too: background a walker uncovers stays
    /// background, a person standing still stays a person. Static when it lies more than
    /// `margin` behind the nearest movable keypoint there (a mask's edge often takes in some
    /// background; never the other way round).
    Label at(const cv::Point2f& p, float z, Motion motion, float margin) const
    {
        if (!(p.x >= 0.0F) || !(p.y >= 0.0F))
            return Label::Unknown;
        const int cx = static_cast<int>(p.x) / kCell, cy = static_cast<int>(p.y) / kCell;
        const std::vector<LabelCount>& counts = motion == Motion::Still ? still : all;
        LabelCount n;
        float near = std::numeric_limits<float>::max();
        for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, rows - 1); ++y)
        {
            for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, cols - 1); ++x)
            {
                n += counts[index(x, y)];
                near = std::min(near, nearest[index(x, y)]);
            }
        }
        if (n.known == 0)
            return Label::Unknown;
        // A strict majority: at half (a person's edge) more background is lost to people than
        // people to background (measured on the walking presets), and the flow test covers
        // the edges of movers.
        if (2 * n.movable <= n.known || (z > 0.0F && z > near + margin))
            return Label::Static;
        return Label::Movable;
    }
};
}  // namespace

MovableLabelTracker::MovableLabelTracker(double keep_s, double depthMargin)
    : keep_s_(keep_s), depthMargin_(static_cast<float>(depthMargin))
{
}

const MovableLabelTracker::Kept* MovableLabelTracker::find(uint64_t frameId) const
{
    for (const auto& k : frames_)
        if (k.tracks.frameId == frameId)
            return &k;
    return nullptr;
}

void MovableLabelTracker::labelFromImage(Kept& frame, const cv::Mat& image) const
{
    const auto& kps = frame.tracks.keypoints;
    frame.labels.assign(kps.size(), Label::Static);
    for (size_t i = 0; i < kps.size(); ++i)
    {
        const long u = std::lround(kps[i].x), v = std::lround(kps[i].y);
        if (u < 0 || v < 0 || u >= image.cols || v >= image.rows)
            frame.labels[i] = Label::Unknown;
        else if (image.at<uint8_t>(static_cast<int>(v), static_cast<int>(u)) != 0)
            frame.labels[i] = Label::Movable;
    }
}

void MovableLabelTracker::labelFromReference(Kept& frame) const
{
    const FrameTracks& t = frame.tracks;
    frame.labels.assign(t.keypoints.size(), Label::Unknown);
    if (t.framesBack == 0 || t.framesBack > t.frameId)
        return;
    const Kept* ref = find(t.frameId - t.framesBack);
    if (!ref || ref->labels.empty())
        return;
    const LabelCells cells(ref->tracks, ref->labels);
    for (size_t i = 0; i < t.keypoints.size() && i < t.inReference.size(); ++i)
        frame.labels[i] =
            cells.at(t.inReference[i], i < t.depth.size() ? t.depth[i] : 0.0F,
                     i < t.motion.size() ? t.motion[i] : Motion::Untracked, depthMargin_);
}

const std::vector<MovableLabelTracker::Label>& MovableLabelTracker::add(FrameTracks frame)
{
    Kept k;
    k.tracks = std::move(frame);
    labelFromReference(k);
    frames_.push_back(std::move(k));
    const double newest = frames_.back().tracks.timestamp;
    while (frames_.size() > kMaxKept ||
           (frames_.size() > 1 &&
            newest - frames_.front().tracks.timestamp > keep_s_ + core::kTimeTolerance_s))
        frames_.pop_front();
    return frames_.back().labels;
}

void MovableLabelTracker::setMask(uint64_t frameId, const cv::Mat& image)
{
    CV_Assert(image.type() == CV_8UC1);
    // Frames a little before the keyframe: people moved a few pixels at most; the dilation
    // keeps a keypoint on a person's edge on the person.
    cv::Mat grown;
    cv::dilate(image, grown, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(9, 9)));
    for (auto& k : frames_)
    {
        const uint64_t id = k.tracks.frameId;
        if (id + kDirectFrames > frameId && id <= frameId)
            labelFromImage(k, id == frameId ? image : grown);
        else if (id > frameId)
            labelFromReference(k);
    }
}

cv::Mat MovableLabelTracker::movingParts(uint64_t frameId, const cv::Mat& image,
                                         double fraction) const
{
    CV_Assert(image.type() == CV_8UC1);
    cv::Mat moving = cv::Mat::zeros(image.size(), CV_8UC1);
    const Kept* k = find(frameId);
    if (!k)
        return moving;
    cv::Mat parts;
    const int n = cv::connectedComponents(image != 0, parts, 8, CV_32S);
    std::vector<int> movingCount(static_cast<size_t>(n), 0), tracked(static_cast<size_t>(n), 0);
    const FrameTracks& t = k->tracks;
    for (size_t i = 0; i < t.keypoints.size() && i < t.motion.size(); ++i)
    {
        const long u = std::lround(t.keypoints[i].x), v = std::lround(t.keypoints[i].y);
        if (u < 0 || v < 0 || u >= image.cols || v >= image.rows ||
            t.motion[i] == Motion::Untracked)
            continue;
        const auto part =
            static_cast<size_t>(parts.at<int>(static_cast<int>(v), static_cast<int>(u)));
        tracked[part]++;
        movingCount[part] += t.motion[i] == Motion::Moving ? 1 : 0;
    }
    for (int part = 1; part < n; ++part)
        if (static_cast<double>(movingCount[static_cast<size_t>(part)]) >
            fraction * static_cast<double>(tracked[static_cast<size_t>(part)]))
            moving.setTo(255, parts == part);
    return moving;
}
}  // namespace smap::dynamic
