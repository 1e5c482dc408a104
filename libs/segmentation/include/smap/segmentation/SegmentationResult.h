// What a segmenter produces: per-pixel class probabilities and the most likely label.
#pragma once

#include <opencv2/core/mat.hpp>

namespace smap::segmentation
{
struct SegmentationResult
{
    /// CV_32FC1, one row per label of the label set (row k = class id k), one column per pixel
    /// (column v * width + u); every column sums to 1.
    cv::Mat probabilities;
    /// CV_8UC1 height x width: the arg max of each column (class ids of the label set), or
    /// 255 (void) where a label image says nothing (LabelImageSegmenter).
    cv::Mat labels;

    int width() const { return labels.cols; }
    int height() const { return labels.rows; }
    int labelCount() const { return probabilities.rows; }
    /// Class k's probabilities as a height x width image (a view, no copy).
    cv::Mat plane(int k) const;

    /// The probability of each pixel's label, CV_32FC1 height x width (0 on void pixels).
    cv::Mat labelConfidence() const;

    /// A result from probabilities (labels x (width*height)); computes the labels.
    static SegmentationResult fromProbabilities(cv::Mat probabilities, int width, int height);
    /// Bilinear resampling of the probabilities to another size (renormalised), new labels.
    SegmentationResult resized(int newWidth, int newHeight) const;
};

/// Row-wise softmax of a labels x pixels matrix of scores (logits), in place.
void softmaxColumns(cv::Mat& scores);
/// Arg max of each column of a labels x pixels matrix, as a height x width CV_8UC1 image.
cv::Mat argmaxColumns(const cv::Mat& probabilities, int width, int height);
}  // namespace smap::segmentation
