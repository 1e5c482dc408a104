// ORB features over an image pyramid, spread over the image with a grid and FAST threshold
// adaptation (ORB-SLAM's scheme): oriented FAST corners, 256-bit rotated binary descriptors.
#pragma once

#include <array>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/features/FeatureSet.h"
#include "smap/features/OrbParameters.h"

namespace smap::features
{
class OrbExtractor
{
public:
    explicit OrbExtractor(const OrbParameters& params);

    /// Keypoints and descriptors of a CV_8UC1 image (a CV_8UC3 BGR image is converted).
    /// `undistorted`, `depth` and `rightU` are left for undistortKeypoints() / assignDepth().
    /// `fill_last` (optional, CV_8UC1 of any size, stretched over the image): corners where it
    /// is non-zero are taken only after every other cell's, so that the budget goes to the rest
    /// of the image first (e.g. regions the dynamic filter found moving).
    FeatureSet extract(const cv::Mat& image, const cv::Mat& fill_last = {}) const;

    const OrbParameters& parameters() const { return params_; }
    const ScalePyramid& pyramid() const { return pyramid_; }

    /// Pixels kept free at every level's border (descriptor and orientation patches fit).
    static constexpr int kBorder = 16;

private:
    void detectLevel(const cv::Mat& level, int wanted, const cv::Mat& fill_last, float scale,
                     cv::Size image_size, std::vector<cv::KeyPoint>& out) const;
    float orientation(const cv::Mat& level, cv::Point2f p) const;
    void describe(const cv::Mat& blurred, const cv::KeyPoint& kp_level, uint8_t* out) const;

    OrbParameters params_;
    ScalePyramid pyramid_;
    std::vector<int> featuresPerLevel_;
    // 256 point pairs within the patch disk, pair i's points at 2i and 2i + 1
    static constexpr size_t kSamplePoints = 512;
    std::array<float, kSamplePoints> patternX_{};
    std::array<float, kSamplePoints> patternY_{};
    std::array<int, 16> circleHalfWidth_{};  // orientation disk, radius 15
};
}  // namespace smap::features
