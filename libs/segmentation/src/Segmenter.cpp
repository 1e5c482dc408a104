#include "smap/segmentation/Segmenter.h"

namespace smap::segmentation
{
SegmentationResult Segmenter::segment(const core::RgbdFrame& frame)
{
    return segmentNative(frame).resized(frame.colour.cols, frame.colour.rows);
}
}  // namespace smap::segmentation
