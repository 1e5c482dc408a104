// The paper's Table III frame-level segmentation scores (docs/method.md section 5) and per-class
// IoU. Per frame and class: the class is present in the ground truth or not, and correctly
// segmented (IoU >= iou_threshold) or predicted at all. TP: present and correctly segmented;
// FN: present, not correctly segmented; FP: absent but predicted; TN: absent, not predicted.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "smap/core/JsonWriter.h"

namespace smap::eval
{
struct SegmentationScoreOptions
{
    /// "Correctly segmented": IoU of predicted and true masks at least this (the paper does
    /// not say; we state it in every output).
    double iouThreshold = 0.5;
    /// A class is present (in truth) or predicted when it covers at least this fraction of the
    /// frame's scored pixels.
    double minAreaFraction = 0.001;
    /// Ground-truth label of pixels left out of scoring (255 = void); -1: none is.
    int voidLabel = 255;
    /// Boundary band half-width (px) for the band IoU around true class edges.
    int bandRadius = 5;
};

struct ClassSegmentationScore
{
    int id = 0;
    std::string name;
    size_t tp = 0, fn = 0, fp = 0, tn = 0;
    /// Pixel counts summed over frames: IoU = intersection / union.
    double intersection = 0.0, unionArea = 0.0;
    /// The same within bandRadius px of the true class boundary (frames where present).
    double bandIntersection = 0.0, bandUnion = 0.0;

    double fpr() const;        ///< FP / (FP + TN)
    double fnr() const;        ///< FN / (TP + FN)
    double recall() const;     ///< TP / (TP + FN)
    double precision() const;  ///< TP / (TP + FP)
    double pwc() const;        ///< (FN + FP) / all frames
    double iou() const;
    double bandIou() const;
};

class SegmentationScore
{
public:
    /// Classes to score as (id, name) pairs.
    SegmentationScore(const std::vector<std::pair<int, std::string>>& classes,
                      SegmentationScoreOptions options = {});

    /// Scores one frame: CV_8UC1 label images of the same size. Throws std::invalid_argument
    /// when they are not.
    void addFrame(const cv::Mat& truth, const cv::Mat& predicted);

    size_t frames() const { return frames_; }
    const std::vector<ClassSegmentationScore>& classes() const { return classes_; }
    const SegmentationScoreOptions& options() const { return options_; }

    /// A table: class, frames present, TP FN FP TN, FPR FNR Re Pr PWC, IoU, band IoU.
    std::string toText() const;
    core::JsonValue toJson() const;

private:
    std::vector<ClassSegmentationScore> classes_;
    SegmentationScoreOptions options_;
    size_t frames_ = 0;
};
}  // namespace smap::eval
