// Everything segmentation reads from the configuration: [segmentation] picks the backend and
// the label set, [onnx], [label_images] and [crf] configure the parts. Loaded once.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <string>

#include "smap/segmentation/DenseCrf.h"
#include "smap/segmentation/LabelImageSegmenter.h"
#include "smap/segmentation/OnnxSegmenter.h"

namespace smap::segmentation
{
struct SegmentationParameters : public mrpt::config::CLoadableOptions
{
    /// "onnx" (a CNN through cv::dnn), "label_images" (precomputed label images) or "none"
    /// (no segmentation: every pixel is void).
    std::string backend = "onnx";
    /// Label table (config/labels/*.csv); empty = the built-in PASCAL VOC table.
    std::string labels;
    OnnxSegmenterParameters onnx;
    LabelImageParameters label_images;
    DenseCrfParameters crf;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};

/// The label set of `params` (loaded from its CSV, or PASCAL VOC).
core::LabelSet loadLabelSet(const SegmentationParameters& params);

/// The configured backend, wrapped in the dense CRF when [crf] enabled; nullptr for "none". Throws
/// core::InputError for a bad model, folder or label table.
std::unique_ptr<Segmenter> makeSegmenter(const SegmentationParameters& params);
}  // namespace smap::segmentation
