#include "smap/segmentation/ZoomSegmenter.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "smap/core/LabelSet.h"

namespace smap::segmentation
{
namespace
{
/// A window of `size` with `centre` across its middle and a third of the way down, inside
/// the frame.
cv::Rect windowAround(const cv::Point2d& centre, cv::Size size, cv::Size frame)
{
    const int x = static_cast<int>(std::lround(centre.x - size.width / 2.0));
    const int y = static_cast<int>(std::lround(centre.y - size.height / 3.0));
    return {std::clamp(x, 0, frame.width - size.width),
            std::clamp(y, 0, frame.height - size.height), size.width, size.height};
}
/// A pixel's probability of the movable classes.
float movableMass(const cv::Mat& probabilities, int column, const std::vector<bool>& movable)
{
    float m = 0.0F;
    for (int k = 0; k < probabilities.rows; ++k)
        if (static_cast<size_t>(k) < movable.size() && movable[k])
            m += probabilities.at<float>(k, column);
    return m;
}

/// The crop's distribution replaces the first pass's at each pixel of `place` where it gives
/// the movable classes more: the closer look adds what the first pass missed, and takes away
/// nothing it found (a crop's edge sees less of a person than the whole frame does).
void takeWhereMoreMovable(const SegmentationResult& closer, const cv::Rect& place,
                          const std::vector<bool>& movable, SegmentationResult& first)
{
    for (int v = 0; v < place.height; ++v)
    {
        for (int u = 0; u < place.width; ++u)
        {
            const int from = v * closer.width() + u;
            const int to = (place.y + v) * first.width() + place.x + u;
            if (movableMass(closer.probabilities, from, movable) >
                movableMass(first.probabilities, to, movable))
                closer.probabilities.col(from).copyTo(first.probabilities.col(to));
        }
    }
}
}  // namespace

std::vector<cv::Rect> zoomWindows(const cv::Mat& labels, const std::vector<bool>& movable,
                                  cv::Size frameSize, int maxCrops)
{
    std::vector<cv::Rect> windows;
    if (maxCrops <= 0 || labels.empty())
        return windows;
    cv::Mat components, stats, centroids;
    const int n = cv::connectedComponentsWithStats(core::classMask(labels, movable), components,
                                                   stats, centroids, 8, CV_32S);
    const double minArea = ZoomSegmenter::kMinRegionFraction * labels.total();
    std::vector<int> regions;
    for (int k = 1; k < n; ++k)
        if (stats.at<int>(k, cv::CC_STAT_AREA) >= minArea)
            regions.push_back(k);
    std::stable_sort(
        regions.begin(), regions.end(),
        [&stats](int a, int b)
        { return stats.at<int>(a, cv::CC_STAT_AREA) > stats.at<int>(b, cv::CC_STAT_AREA); });
    const double sx = static_cast<double>(frameSize.width) / labels.cols;
    const double sy = static_cast<double>(frameSize.height) / labels.rows;
    const cv::Size size(frameSize.width / 2, frameSize.height / 2);
    for (int k : regions)
    {
        const cv::Point2d centre(
            (stats.at<int>(k, cv::CC_STAT_LEFT) + stats.at<int>(k, cv::CC_STAT_WIDTH) / 2.0) * sx,
            (stats.at<int>(k, cv::CC_STAT_TOP) + stats.at<int>(k, cv::CC_STAT_HEIGHT) / 2.0) * sy);
        const bool seen = std::any_of(windows.begin(), windows.end(),
                                      [&centre](const cv::Rect& w) {
                                          return w.contains(cv::Point(static_cast<int>(centre.x),
                                                                      static_cast<int>(centre.y)));
                                      });
        if (!seen)
            windows.push_back(windowAround(centre, size, frameSize));
        if (static_cast<int>(windows.size()) >= maxCrops)
            break;
    }
    return windows;
}

ZoomSegmenter::ZoomSegmenter(std::unique_ptr<Segmenter> inner, const ZoomParameters& params)
    : Segmenter("ZoomSegmenter", inner->labels()),
      inner_(std::move(inner)),
      params_(params),
      movable_(labels().movable(params.min_prior))
{
}

SegmentationResult ZoomSegmenter::segmentNative(const core::RgbdFrame& frame)
{
    SegmentationResult first = inner_->segmentNative(frame);
    // A crop of half the frame must hold at least the network's input: on a smaller frame the
    // second look would only see the same pixels enlarged.
    if (frame.colour.cols < 2 * first.width() || frame.colour.rows < 2 * first.height())
        return first;
    const std::vector<cv::Rect> windows =
        zoomWindows(first.labels, movable_, frame.colour.size(), params_.crops);
    for (const cv::Rect& w : windows)
        lookAgain(frame, w, first);
    if (!windows.empty())
        first.labels = argmaxColumns(first.probabilities, first.width(), first.height());
    return first;
}

void ZoomSegmenter::lookAgain(const core::RgbdFrame& frame, const cv::Rect& window,
                              SegmentationResult& first)
{
    core::RgbdFrame crop;
    crop.name = frame.name;
    crop.colour = frame.colour(window).clone();
    const double sx = static_cast<double>(first.width()) / frame.colour.cols;
    const double sy = static_cast<double>(first.height()) / frame.colour.rows;
    const cv::Rect place(static_cast<int>(std::lround(window.x * sx)),
                         static_cast<int>(std::lround(window.y * sy)),
                         static_cast<int>(std::lround(window.width * sx)),
                         static_cast<int>(std::lround(window.height * sy)));
    const cv::Rect inside = place & cv::Rect(0, 0, first.width(), first.height());
    if (inside.area() == 0)
        return;
    const SegmentationResult closer =
        inner_->segmentNative(crop).resized(inside.width, inside.height);
    takeWhereMoreMovable(closer, inside, movable_, first);
}

std::string ZoomSegmenter::description() const
{
    return inner_->description() + mrpt::format(" + zoom x2 (%d crops)", params_.crops);
}
}  // namespace smap::segmentation
