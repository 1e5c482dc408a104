// Binary descriptor distances and brute-force matching with Lowe's ratio test.
#pragma once

#include <cstdint>
#include <cstring>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace smap::features
{
/// Hamming distance between two 256-bit descriptors. Bit-parallel counting, inlined: without
/// a popcnt instruction in the baseline ISA, __builtin_popcountll is a library call per word.
inline int descriptorDistance(const uint8_t* a, const uint8_t* b)
{
    constexpr uint64_t k1 = 0x5555555555555555ULL, k2 = 0x3333333333333333ULL,
                       k4 = 0x0f0f0f0f0f0f0f0fULL;
    uint64_t sum = 0;
    for (int i = 0; i < 4; ++i)
    {
        uint64_t x = 0, y = 0;
        std::memcpy(&x, a + 8 * i, 8);
        std::memcpy(&y, b + 8 * i, 8);
        x ^= y;
        x -= (x >> 1U) & k1;
        x = (x & k2) + ((x >> 2U) & k2);
        sum += (x + (x >> 4U)) & k4;  // per-byte counts: at most 4 x 8 = 32 each
    }
    // Bytes into 16-bit lanes (at most 64 each), then all lanes into the top one (at most 256).
    constexpr uint64_t kBytes = 0x00ff00ff00ff00ffULL, kLanes = 0x0001000100010001ULL;
    const uint64_t lanes = (sum & kBytes) + ((sum >> 8U) & kBytes);
    return static_cast<int>((lanes * kLanes) >> 48U);
}

struct DescriptorMatch
{
    size_t query = 0;
    size_t train = 0;
    int distance = 0;
};

/// For every query row in `query_rows` (all rows when empty), its nearest train row in
/// `train_rows` (all when empty) when the distance is at most `max_distance` and below
/// `ratio` times the second-nearest. Each train row is used at most once (the closest query
/// wins), so the result is a one-to-one set.
std::vector<DescriptorMatch> matchWithRatioTest(const cv::Mat& query, const cv::Mat& train,
                                                float ratio, int max_distance,
                                                const std::vector<size_t>& query_rows = {},
                                                const std::vector<size_t>& train_rows = {});
class FeatureGrid;

/// Like matchWithRatioTest, but each query keypoint only looks at train keypoints within
/// `radius` px (square window, undistorted coordinates, pyramid level within +-1) found through
/// `train_grid`: frame-to-frame matching where the image motion is bounded. Only the rows in
/// `query_rows` are matched when it is not empty.
std::vector<DescriptorMatch> matchWithinRadius(const cv::Mat& query,
                                               const std::vector<cv::KeyPoint>& query_keypoints,
                                               const std::vector<cv::Point2f>& query_points,
                                               const cv::Mat& train, const FeatureGrid& train_grid,
                                               float radius, float ratio, int max_distance,
                                               const std::vector<size_t>& query_rows = {});
}  // namespace smap::features
