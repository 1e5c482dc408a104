#include "smap/dynamic/MovableLabelTracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace smap::dynamic
{
namespace
{
constexpr int kCell = 8;

/// Per 8 px cell of a frame: how many of its keypoints are labelled, how many movable.
struct LabelCells
{
    int cols = 0, rows = 0;
    std::vector<int> known, movable;
    std::vector<float> nearest;  ///< nearest movable keypoint (m)

    size_t index(int cx, int cy) const
    {
        return static_cast<size_t>(cy) * static_cast<size_t>(cols) + static_cast<size_t>(cx);
    }

    LabelCells(const std::vector<cv::Point2f>& keypoints, const std::vector<float>& depth,
               const std::vector<MovableLabelTracker::Label>& labels)
    {
        for (const auto& p : keypoints)
        {
            cols = std::max(cols, static_cast<int>(p.x) / kCell + 1);
            rows = std::max(rows, static_cast<int>(p.y) / kCell + 1);
        }
        known.assign(static_cast<size_t>(cols) * static_cast<size_t>(rows), 0);
        movable.assign(known.size(), 0);
        nearest.assign(known.size(), std::numeric_limits<float>::max());
        for (size_t i = 0; i < keypoints.size(); ++i)
        {
            if (labels[i] == MovableLabelTracker::Label::Unknown || !(keypoints[i].x >= 0.0F) ||
                !(keypoints[i].y >= 0.0F))
                continue;
            const size_t c = index(static_cast<int>(keypoints[i].x) / kCell,
                                   static_cast<int>(keypoints[i].y) / kCell);
            known[c]++;
            if (labels[i] != MovableLabelTracker::Label::Movable)
                continue;
            movable[c]++;
            if (i < depth.size() && depth[i] > 0.0F)
                nearest[c] = std::min(nearest[c], depth[i]);
        }
    }

    /// The majority label of the 3 x 3 cells around pixel p, for a keypoint at depth z (<= 0:
    /// unknown): Static when it lies more than `margin` behind the nearest movable keypoint
    /// there (a mask's edge often takes in some background; never the other way round).
    MovableLabelTracker::Label at(const cv::Point2f& p, float z, float margin) const
    {
        if (!(p.x >= 0.0F) || !(p.y >= 0.0F))
            return MovableLabelTracker::Label::Unknown;
        const int cx = static_cast<int>(p.x) / kCell, cy = static_cast<int>(p.y) / kCell;
        int k = 0, m = 0;
        float near = std::numeric_limits<float>::max();
        for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, rows - 1); ++y)
        {
            for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, cols - 1); ++x)
            {
                const size_t c = index(x, y);
                k += known[c];
                m += movable[c];
                near = std::min(near, nearest[c]);
            }
        }
        if (k == 0)
            return MovableLabelTracker::Label::Unknown;
        // A strict majority: at half (a person's edge) more background is lost to people than
        // people to background (measured on the walking presets), and the flow test covers
        // the edges of movers.
        if (2 * m <= k || (z > 0.0F && z > near + margin))
            return MovableLabelTracker::Label::Static;
        return MovableLabelTracker::Label::Movable;
    }
};
}  // namespace

MovableLabelTracker::MovableLabelTracker(size_t keep, double depthMargin)
    : keep_(std::max<size_t>(keep, 1)), depthMargin_(static_cast<float>(depthMargin))
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
    const LabelCells cells(ref->tracks.keypoints, ref->tracks.depth, ref->labels);
    for (size_t i = 0; i < t.keypoints.size() && i < t.inReference.size(); ++i)
        frame.labels[i] =
            cells.at(t.inReference[i], i < t.depth.size() ? t.depth[i] : 0.0F, depthMargin_);
}

const std::vector<MovableLabelTracker::Label>& MovableLabelTracker::add(FrameTracks frame)
{
    Kept k;
    k.tracks = std::move(frame);
    labelFromReference(k);
    frames_.push_back(std::move(k));
    while (frames_.size() > keep_)
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
}  // namespace smap::dynamic
