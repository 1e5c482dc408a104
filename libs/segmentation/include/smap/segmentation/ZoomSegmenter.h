// A second, closer look at the people: a segmenter run again on crops of the full-resolution
// frame around its movable-class regions, a crop's probabilities replacing the first pass's
// where they make a pixel more likely a person (or another movable class). A network at 320x240
// misses what is small in the view (a seated person's legs under a table); on a crop of half the
// frame's size it sees that part at twice the resolution, as the same network exported at 640x480
// would, at the cost of one pass per crop instead of four times the pixels everywhere.
#pragma once

#include <memory>
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

#include "smap/segmentation/Segmenter.h"

namespace smap::segmentation
{
/// [segmentation] zoom_* keys.
struct ZoomParameters
{
    /// Crops per frame, around the largest movable-class regions first; 0 disables the zoom.
    int crops = 2;
    /// The classes looked at again: those whose dynamic prior (the label table's) is at least
    /// this (PASCAL VOC: person, and the animals and vehicles).
    double min_prior = 0.5;
};

/// Where to look again, in frame pixels: for each movable-class region of `labels` (the first
/// pass, at its own resolution) of at least kMinRegionFraction of its pixels, largest first, a
/// window of half the frame's width and height, centred on the region across and with the
/// region's centre a third of the way down (what a person's first pass misses is mostly below:
/// legs behind furniture), kept inside the frame. A region whose centre falls in a window
/// already chosen gets none; at most `maxCrops` windows.
std::vector<cv::Rect> zoomWindows(const cv::Mat& labels, const std::vector<bool>& movable,
                                  cv::Size frameSize, int maxCrops);

class ZoomSegmenter : public Segmenter
{
public:
    /// Regions below this fraction of the first pass's pixels get no crop (a speck of a
    /// label is more likely a false positive than a person far away).
    static constexpr double kMinRegionFraction = 0.002;

    ZoomSegmenter(std::unique_ptr<Segmenter> inner, const ZoomParameters& params);
    /// The inner segmenter on the frame, then on each zoomWindows crop of the full-resolution
    /// colour image; a crop's probabilities, resampled to the window's place in the first
    /// pass's grid, replace the first pass's at the pixels where they give the movable classes
    /// more probability (the labels follow): the closer look adds what the first pass missed
    /// and removes nothing it found. No crop on a frame smaller than twice the inner
    /// segmenter's working resolution (its crops would only enlarge the same pixels).
    SegmentationResult segmentNative(const core::RgbdFrame& frame) override;
    std::string description() const override;
    Segmenter& inner() { return *inner_; }

private:
    void lookAgain(const core::RgbdFrame& frame, const cv::Rect& window, SegmentationResult& first);

    std::unique_ptr<Segmenter> inner_;
    ZoomParameters params_;
    std::vector<bool> movable_;
};
}  // namespace smap::segmentation
