// Any segmenter followed by dense-CRF refinement at the segmenter's working resolution.
#pragma once

#include <memory>

#include "smap/segmentation/DenseCrf.h"
#include "smap/segmentation/Segmenter.h"

namespace smap::segmentation
{
class CrfSegmenter : public Segmenter
{
public:
    CrfSegmenter(std::unique_ptr<Segmenter> inner, const DenseCrfParameters& params);

    /// The inner segmenter's probabilities refined by the CRF, on the frame's colour resized
    /// (INTER_AREA) to the inner segmenter's working resolution.
    SegmentationResult segmentNative(const core::RgbdFrame& frame) override;
    std::string description() const override;

    Segmenter& inner() { return *inner_; }
    const DenseCrf& crf() const { return crf_; }

private:
    std::unique_ptr<Segmenter> inner_;
    DenseCrf crf_;
};
}  // namespace smap::segmentation
