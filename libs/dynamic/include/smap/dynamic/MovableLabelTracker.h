// Semantic labels that follow people: a keyframe's movable-class mask labels the keypoints of the
// keyframe (and of the frame or two before it), and every later frame's keypoints take the label
// of where the strong dynamic filter's Lucas-Kanade found them in their reference frame (the
// majority of that frame's labelled keypoints in the 3 x 3 cells of 8 px around), unless it lies
// farther than the nearest movable keypoints there (background a person uncovered). A keypoint
// the flow test found still counts only the keypoints there that were still too: background a
// walker uncovers at the walker's own depth stays background, a person who stands still stays a
// person. A walking person's label walks with them, which a mask warped by the camera pose alone
// cannot do.
#pragma once

#include <cstdint>
#include <deque>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace smap::dynamic
{
class MovableLabelTracker
{
public:
    enum class Label : int8_t
    {
        Unknown = -1,  ///< no labelled keypoint near its track (or no track)
        Static = 0,
        Movable = 1
    };
    /// What the flow test said of a keypoint in its own frame.
    enum class Motion : uint8_t
    {
        Untracked,  ///< no flow measurement
        Still,
        Moving
    };

    /// Keeps the frames of the last `keep_s` seconds (at least the masks' largest age plus the
    /// filter's gap; at most kMaxKept frames). A keypoint farther than `depthMargin` (m)
    /// behind the nearest movable keypoint its track reaches is static.
    MovableLabelTracker(double keep_s, double depthMargin);
    static constexpr size_t kMaxKept = 1000;

    struct FrameTracks
    {
        uint64_t frameId = 0;
        double timestamp = 0.0;   ///< s
        uint64_t framesBack = 0;  ///< the reference frame is frameId - framesBack (0: none)
        std::vector<cv::Point2f> keypoints;    ///< pixel positions
        std::vector<cv::Point2f> inReference;  ///< per keypoint; negative: not tracked
        std::vector<float> depth;              ///< per keypoint (m; <= 0: none)
        std::vector<Motion> motion;            ///< per keypoint (missing: Untracked)
    };
    /// Adds the newest frame (increasing ids) and labels its keypoints from its reference
    /// frame; returns the labels (all Unknown when the reference has none).
    const std::vector<Label>& add(FrameTracks frame);

    /// A keyframe's mask (CV_8UC1, non-zero = movable; pixels as the keypoints): labels the
    /// kept frames from two before it up to it from the image, then each later kept frame
    /// from its reference, in order.
    void setMask(uint64_t frameId, const cv::Mat& image);

    /// The parts (connected regions) of a kept frame's mask (CV_8UC1, non-zero = movable) where
    /// the flow test found more than `fraction` of the keypoints it measured moving, on that
    /// frame: CV_8UC1, 255 there; all 0 when the frame is not kept.
    cv::Mat movingParts(uint64_t frameId, const cv::Mat& image, double fraction) const;

private:
    struct Kept
    {
        FrameTracks tracks;
        std::vector<Label> labels;
    };
    /// How many frames up to the keyframe take their labels from its image directly.
    static constexpr uint64_t kDirectFrames = 3;

    void labelFromImage(Kept& frame, const cv::Mat& image) const;
    void labelFromReference(Kept& frame) const;
    const Kept* find(uint64_t frameId) const;

    double keep_s_;
    float depthMargin_;
    std::deque<Kept> frames_;
};
}  // namespace smap::dynamic
