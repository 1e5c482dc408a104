#include "smap/segmentation/SegmentationParameters.h"

#include <mrpt/config/CConfigFileBase.h>

#include "smap/core/InputError.h"
#include "smap/segmentation/CrfSegmenter.h"

namespace smap::segmentation
{
void SegmentationParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                const std::string&)
{
    const char* s = "segmentation";
    backend = cfg.read_string(s, "backend", backend);
    labels = cfg.read_string(s, "labels", labels);
    if (backend != "onnx" && backend != "label_images" && backend != "none")
        throw core::InputError("[segmentation] backend = '" + backend +
                               "' is not one of: onnx, label_images, none");
    onnx.loadFromConfigFile(cfg, "onnx");
    label_images.loadFromConfigFile(cfg, "label_images");
    crf.loadFromConfigFile(cfg, "crf");
}

void SegmentationParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                              const std::string&) const
{
    cfg.write("segmentation", "backend", backend);
    cfg.write("segmentation", "labels", labels);
    onnx.saveToConfigFile(cfg, "onnx");
    label_images.saveToConfigFile(cfg, "label_images");
    crf.saveToConfigFile(cfg, "crf");
}

core::LabelSet loadLabelSet(const SegmentationParameters& params)
{
    return params.labels.empty() ? core::LabelSet::pascalVoc()
                                 : core::LabelSet::loadCsv(params.labels);
}

std::unique_ptr<Segmenter> makeSegmenter(const SegmentationParameters& params)
{
    if (params.backend == "none")
        return nullptr;
    core::LabelSet labels = loadLabelSet(params);
    std::unique_ptr<Segmenter> s;
    if (params.backend == "onnx")
        s = std::make_unique<OnnxSegmenter>(params.onnx, std::move(labels));
    else
        s = std::make_unique<LabelImageSegmenter>(params.label_images, std::move(labels));
    if (params.crf.enabled)
        s = std::make_unique<CrfSegmenter>(std::move(s), params.crf);
    return s;
}
}  // namespace smap::segmentation
