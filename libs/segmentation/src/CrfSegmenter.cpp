#include "smap/segmentation/CrfSegmenter.h"

#include <mrpt/core/format.h>
#include <mrpt/system/CTicTac.h>

#include <opencv2/imgproc.hpp>

#include "smap/core/LabelSet.h"

namespace smap::segmentation
{
CrfSegmenter::CrfSegmenter(std::unique_ptr<Segmenter> inner, const DenseCrfParameters& params)
    : Segmenter("CrfSegmenter", inner->labels()),
      inner_(std::move(inner)),
      crf_(params, static_cast<int>(labels().size()))
{
}

SegmentationResult CrfSegmenter::segmentNative(const core::RgbdFrame& frame)
{
    mrpt::system::CTicTac timer;
    const SegmentationResult r = inner_->segmentNative(frame);
    const double innerMs = 1e3 * timer.Tac();
    timer.Tic();
    cv::Mat colour = frame.colour;
    if (colour.cols != r.width() || colour.rows != r.height())
        cv::resize(frame.colour, colour, cv::Size(r.width(), r.height()), 0, 0,
                   colour.cols > r.width() ? cv::INTER_AREA : cv::INTER_LINEAR);
    auto refined = SegmentationResult::fromProbabilities(crf_.refine(colour, r.probabilities),
                                                         r.width(), r.height());
    // Where the inner segmenter said nothing (void pixels of a label image, uniform
    // distributions), the CRF would hand out its neighbours' labels: those stay void.
    refined.labels.setTo(core::LabelSet::kVoid, r.labels == core::LabelSet::kVoid);
    MRPT_LOG_DEBUG_FMT("%s: %s %.1f ms, crf %.1f ms", frame.name.c_str(),
                       inner_->description().c_str(), innerMs, 1e3 * timer.Tac());
    return refined;
}

std::string CrfSegmenter::description() const
{
    return inner_->description() +
           mrpt::format(" + dense CRF (%d iterations)", crf_.parameters().iterations);
}
}  // namespace smap::segmentation
