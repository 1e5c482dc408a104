// Everything segmentation reads from the configuration: [segmentation] picks the backend and
// the label set, [onnx], [label_images] and [crf] configure the parts. Loaded once.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <string>

#include "smap/segmentation/DenseCrf.h"
#include "smap/segmentation/LabelImageSegmenter.h"
#include "smap/segmentation/OnnxSegmenter.h"
#include "smap/segmentation/ZoomSegmenter.h"

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
    /// zoom_crops, zoom_min_prior: the second look at movable-class regions (onnx only).
    ZoomParameters zoom;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};

/// The label set of `params` (loaded from its CSV, or PASCAL VOC).
core::LabelSet loadLabelSet(const SegmentationParameters& params);

/// The segmentation model that ships with the project, in the data folder
/// (core::dataDirectory(): models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx), whether or not
/// it exists there.
std::string shippedModelPath();

/// With backend = onnx and no [onnx] model configured: sets the shipped model and returns true,
/// or returns false when it is not there (a broken installation) and leaves `params` as they
/// are. True without a change for every other configuration.
bool useShippedModelIfUnset(SegmentationParameters& params);

/// The configured backend, an onnx one with its second look at people (ZoomSegmenter) when
/// zoom_crops > 0, wrapped in the dense CRF when [crf] enabled; nullptr for "none". An
/// onnx backend without a model uses the shipped one (useShippedModelIfUnset). Throws
/// core::InputError for a bad or missing model, folder or label table.
std::unique_ptr<Segmenter> makeSegmenter(const SegmentationParameters& params);
}  // namespace smap::segmentation
