// A frame in, per-pixel class probabilities (and arg max labels) out, in the project's label set.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <string>

#include "smap/core/LabelSet.h"
#include "smap/core/RgbdFrame.h"
#include "smap/segmentation/SegmentationResult.h"

namespace smap::segmentation
{
/// Segmenters are meant for keyframes: each call is a whole network pass (tens of ms). One
/// instance may be created on one thread and used on another (a worker), but is not to be
/// called from two threads at once.
class Segmenter : public mrpt::system::COutputLogger
{
public:
    Segmenter(const std::string& loggerName, core::LabelSet labels)
        : COutputLogger(loggerName), labels_(std::move(labels))
    {
    }
    ~Segmenter() override = default;
    Segmenter(const Segmenter&) = delete;
    Segmenter& operator=(const Segmenter&) = delete;

    /// Probabilities and labels at the frame's resolution. Throws core::InputError when the
    /// frame cannot be segmented (no label image for it, wrong image type).
    SegmentationResult segment(const core::RgbdFrame& frame);

    /// Probabilities at the segmenter's own working resolution (a network's input size, say),
    /// which has the frame's aspect ratio; `segment` resamples this to the frame.
    virtual SegmentationResult segmentNative(const core::RgbdFrame& frame) = 0;

    /// A short description for logs and summaries ("onnx espnet...onnx 320x240 + crf").
    virtual std::string description() const = 0;

    const core::LabelSet& labels() const { return labels_; }

private:
    core::LabelSet labels_;
};
}  // namespace smap::segmentation
