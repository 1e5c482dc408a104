#include "smap/features/OrbExtractor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "smap/core/Rounding.h"

namespace smap::features
{
namespace
{
constexpr int kPatchRadius = 15;   // orientation disk
constexpr int kSampleRadius = 13;  // sample points stay inside the disk after any rotation
constexpr int kDescriptorBits = 256;

// Gaussian sample pairs (BRIEF's "G II" layout, sigma = patch / 5) from a fixed-seed Mersenne
// twister, drawn with our own Box-Muller so that every platform gets the same pattern.
double gaussian(std::mt19937& rng, double sigma)
{
    constexpr double kTwoPi = 6.283185307179586;
    const double u1 = (static_cast<double>(rng()) + 0.5) / 4294967296.0;
    const double u2 = (static_cast<double>(rng()) + 0.5) / 4294967296.0;
    return sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}
}  // namespace

OrbExtractor::OrbExtractor(const OrbParameters& params)
    : params_(params), pyramid_(ScalePyramid::make(params.n_levels, params.scale_factor))
{
    // Features per level follow the area of the level: a geometric series in 1 / scale^2
    // would starve the top levels, ORB-SLAM's choice of 1 / scale keeps them useful.
    const double f = 1.0 / params.scale_factor;
    double perLevel = params.n_features * (1.0 - f) / (1.0 - std::pow(f, params.n_levels));
    int total = 0;
    for (int l = 0; l < params.n_levels - 1; ++l)
    {
        featuresPerLevel_.push_back(static_cast<int>(std::lround(perLevel)));
        total += featuresPerLevel_.back();
        perLevel *= f;
    }
    featuresPerLevel_.push_back(std::max(params.n_features - total, 0));

    std::mt19937 rng(0x5eed0b);
    const double sigma = (2 * kPatchRadius + 1) / 5.0;
    auto samplePoint = [&]()
    {
        for (;;)
        {
            const int px = static_cast<int>(std::lround(gaussian(rng, sigma)));
            const int py = static_cast<int>(std::lround(gaussian(rng, sigma)));
            if (px * px + py * py <= kSampleRadius * kSampleRadius)
                return cv::Point2f(static_cast<float>(px), static_cast<float>(py));
        }
    };
    static_assert(kSamplePoints == 2 * kDescriptorBits, "one pair of points per bit");
    // Pair i's points at 2i and 2i + 1; a pair of one point twice is drawn again.
    for (size_t pair = 0; pair < kSamplePoints / 2;)
    {
        const cv::Point2f first = samplePoint(), second = samplePoint();
        if (first == second)
            continue;
        patternX_[2 * pair] = first.x;
        patternY_[2 * pair] = first.y;
        patternX_[2 * pair + 1] = second.x;
        patternY_[2 * pair + 1] = second.y;
        ++pair;
    }
    for (int v = 0; v <= kPatchRadius; ++v)
        circleHalfWidth_[static_cast<size_t>(v)] =
            static_cast<int>(std::floor(std::sqrt(kPatchRadius * kPatchRadius - v * v + 0.5)));
}

namespace
{
struct Ranked
{
    cv::KeyPoint kp;
    int rank;
    bool last;  ///< in `fill_last`
};

/// Whether a corner of a pyramid level (downscaled by `scale`) falls where `fill_last` (a mask
/// over the whole image, any resolution) is set.
bool inFillLast(const cv::Mat& fill_last, const cv::Point2f& p_level, float scale,
                cv::Size image_size)
{
    if (fill_last.empty())
        return false;
    const int mx =
        std::clamp(static_cast<int>(p_level.x * scale * static_cast<float>(fill_last.cols) /
                                    static_cast<float>(image_size.width)),
                   0, fill_last.cols - 1);
    const int my =
        std::clamp(static_cast<int>(p_level.y * scale * static_cast<float>(fill_last.rows) /
                                    static_cast<float>(image_size.height)),
                   0, fill_last.rows - 1);
    return fill_last.at<uint8_t>(my, mx) != 0;
}

/// FAST corners of a cell at the threshold, else at the fallback threshold; highest response
/// first, ties by position so the order is deterministic.
std::vector<cv::KeyPoint> cellCorners(const cv::Mat& roi, int threshold, int fallback)
{
    std::vector<cv::KeyPoint> cell;
    cv::FAST(roi, cell, threshold, true);
    if (cell.empty())
        cv::FAST(roi, cell, fallback, true);
    std::sort(cell.begin(), cell.end(),
              [](const cv::KeyPoint& a, const cv::KeyPoint& b)
              {
                  if (a.response != b.response)
                      return a.response > b.response;
                  return a.pt.y != b.pt.y ? a.pt.y < b.pt.y : a.pt.x < b.pt.x;
              });
    return cell;
}

/// Round robin over the cells: every cell's best corner before any cell's second best (and all
/// of that outside `fill_last` before any corner inside it).
void sortRoundRobin(std::vector<Ranked>& candidates)
{
    std::sort(candidates.begin(), candidates.end(),
              [](const Ranked& a, const Ranked& b)
              {
                  if (a.last != b.last)
                      return b.last;
                  if (a.rank != b.rank)
                      return a.rank < b.rank;
                  if (a.kp.response != b.kp.response)
                      return a.kp.response > b.kp.response;
                  return a.kp.pt.y != b.kp.pt.y ? a.kp.pt.y < b.kp.pt.y : a.kp.pt.x < b.kp.pt.x;
              });
}
}  // namespace

void OrbExtractor::detectLevel(const cv::Mat& level, int wanted, const cv::Mat& fill_last,
                               float scale, cv::Size image_size,
                               std::vector<cv::KeyPoint>& out) const
{
    // Cells over [border - 3, size - border + 3): FAST never fires within 3 px of its ROI.
    const int x0 = kBorder - 3, y0 = kBorder - 3;
    const int x1 = level.cols - kBorder + 3, y1 = level.rows - kBorder + 3;
    if (x1 - x0 < 10 || y1 - y0 < 10 || wanted <= 0)
        return;
    const int nCols = std::max(1, (x1 - x0) / params_.cell_size);
    const int nRows = std::max(1, (y1 - y0) / params_.cell_size);
    const int cellW = (x1 - x0 + nCols - 1) / nCols, cellH = (y1 - y0 + nRows - 1) / nRows;
    std::vector<Ranked> candidates;
    for (int r = 0; r < nRows; ++r)
    {
        for (int c = 0; c < nCols; ++c)
        {
            const int cx0 = x0 + c * cellW, cy0 = y0 + r * cellH;
            const int cx1 = std::min(cx0 + cellW + 6, x1), cy1 = std::min(cy0 + cellH + 6, y1);
            if (cx1 - cx0 < 7 || cy1 - cy0 < 7)
                continue;
            const cv::Mat roi = level(cv::Rect(cx0, cy0, cx1 - cx0, cy1 - cy0));
            int rank = 0, rankLast = 0;
            for (cv::KeyPoint kp :
                 cellCorners(roi, params_.fast_threshold, params_.min_fast_threshold))
            {
                kp.pt.x += static_cast<float>(cx0);
                kp.pt.y += static_cast<float>(cy0);
                // Overlapping cells (the 6 px apron) may see a corner twice: keep the owner.
                if (kp.pt.x < kBorder || kp.pt.y < kBorder || kp.pt.x >= level.cols - kBorder ||
                    kp.pt.y >= level.rows - kBorder)
                    continue;
                if (kp.pt.x >= cx0 + cellW + 3 || kp.pt.y >= cy0 + cellH + 3 ||
                    (c > 0 && kp.pt.x < cx0 + 3) || (r > 0 && kp.pt.y < cy0 + 3))
                    continue;
                const bool last = inFillLast(fill_last, kp.pt, scale, image_size);
                candidates.push_back({kp, last ? rankLast++ : rank++, last});
            }
        }
    }
    sortRoundRobin(candidates);
    const size_t n = std::min(candidates.size(), static_cast<size_t>(wanted));
    for (size_t i = 0; i < n; ++i)
        out.push_back(candidates[i].kp);
}

float OrbExtractor::orientation(const cv::Mat& level, cv::Point2f p) const
{
    const int cu = static_cast<int>(std::lround(p.x)), cv0 = static_cast<int>(std::lround(p.y));
    int m01 = 0, m10 = 0;
    const uint8_t* centre = level.ptr<uint8_t>(cv0) + cu;
    const auto step = static_cast<int>(level.step1());
    for (int u = -kPatchRadius; u <= kPatchRadius; ++u)
        m10 += u * centre[u];
    for (int v = 1; v <= kPatchRadius; ++v)
    {
        int vSum = 0;
        const int d = circleHalfWidth_[static_cast<size_t>(v)];
        for (int u = -d; u <= d; ++u)
        {
            const int below = centre[u + v * step], above = centre[u - v * step];
            vSum += below - above;
            m10 += u * (below + above);
        }
        m01 += v * vSum;
    }
    return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));
}

void OrbExtractor::describe(const cv::Mat& blurred, const cv::KeyPoint& kp_level,
                            uint8_t* out) const
{
    const float a = kp_level.angle * static_cast<float>(CV_PI / 180.0);
    const float ca = std::cos(a), sa = std::sin(a);
    const int cu = static_cast<int>(std::lround(kp_level.pt.x));
    const int cv0 = static_cast<int>(std::lround(kp_level.pt.y));
    const uint8_t* centre = blurred.ptr<uint8_t>(cv0) + cu;
    const auto step = static_cast<int>(blurred.step1());
    // Every sample point rotated by the keypoint's angle, as an offset from the centre pixel.
    std::array<int, kSamplePoints> offset{};
    for (size_t k = 0; k < kSamplePoints; ++k)
    {
        const int rx = core::roundHalfAway(patternX_[k] * ca - patternY_[k] * sa);
        const int ry = core::roundHalfAway(patternX_[k] * sa + patternY_[k] * ca);
        offset[k] = ry * step + rx;
    }
    for (size_t byte = 0; byte < kDescriptorBits / 8; ++byte)
    {
        uint8_t value = 0;
        for (size_t bit = 0; bit < 8; ++bit)
        {
            const size_t pair = 2 * (byte * 8 + bit);
            if (centre[offset[pair]] < centre[offset[pair + 1]])
                value = static_cast<uint8_t>(value | (1U << bit));
        }
        out[byte] = value;
    }
}

FeatureSet OrbExtractor::extract(const cv::Mat& image, const cv::Mat& fill_last) const
{
    cv::Mat grey;
    if (image.channels() == 3)
        cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    else
        grey = image;
    CV_Assert(grey.type() == CV_8UC1);
    CV_Assert(fill_last.empty() || fill_last.type() == CV_8UC1);

    FeatureSet fs;
    fs.pyramid = pyramid_;
    cv::Mat level = grey;
    std::vector<cv::KeyPoint> levelKps;
    std::vector<uint8_t> descriptors;
    for (int l = 0; l < params_.n_levels; ++l)
    {
        if (l > 0)
        {
            const float s = pyramid_.scale[static_cast<size_t>(l)];
            const cv::Size size(static_cast<int>(std::lround(grey.cols / s)),
                                static_cast<int>(std::lround(grey.rows / s)));
            if (size.width < 2 * kBorder + 8 || size.height < 2 * kBorder + 8)
                break;
            cv::Mat next;
            cv::resize(level, next, size, 0, 0, cv::INTER_LINEAR);
            level = next;
        }
        levelKps.clear();
        const float scale = pyramid_.scale[static_cast<size_t>(l)];
        detectLevel(level, featuresPerLevel_[static_cast<size_t>(l)], fill_last, scale, grey.size(),
                    levelKps);
        if (levelKps.empty())
            continue;
        cv::Mat blurred;
        cv::GaussianBlur(level, blurred, cv::Size(7, 7), 2.0, 2.0, cv::BORDER_REFLECT_101);
        for (cv::KeyPoint& kp : levelKps)
        {
            kp.angle = orientation(level, kp.pt);
            kp.octave = l;
            kp.size = (2 * kPatchRadius + 1) * scale;
            const size_t offset = descriptors.size();
            descriptors.resize(offset + kDescriptorBits / 8);
            describe(blurred, kp, descriptors.data() + offset);
            kp.pt *= scale;
            fs.keypoints.push_back(kp);
        }
    }
    fs.descriptors = cv::Mat(static_cast<int>(fs.keypoints.size()), kDescriptorBits / 8, CV_8UC1);
    if (!fs.keypoints.empty())
        std::copy(descriptors.begin(), descriptors.end(), fs.descriptors.ptr<uint8_t>());
    fs.undistorted.resize(fs.keypoints.size());
    for (size_t i = 0; i < fs.keypoints.size(); ++i)
        fs.undistorted[i] = fs.keypoints[i].pt;
    fs.depth.assign(fs.keypoints.size(), 0.0F);
    fs.rightU.assign(fs.keypoints.size(), -1.0F);
    return fs;
}
}  // namespace smap::features
