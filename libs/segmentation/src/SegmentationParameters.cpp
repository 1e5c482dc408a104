#include "smap/segmentation/SegmentationParameters.h"

#include <mrpt/config/CConfigFileBase.h>

#include <filesystem>
#include <system_error>

#include "smap/core/DataDirectory.h"
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

std::string shippedModelPath()
{
    const std::string dir = core::dataDirectory();
    const std::string relative = "models/espnetv2-voc/espnetv2_s2.0_voc_320x240.onnx";
    return dir.empty() ? relative : (std::filesystem::path(dir) / relative).string();
}

bool useShippedModelIfUnset(SegmentationParameters& params)
{
    if (params.backend != "onnx" || !params.onnx.model.empty())
        return true;
    const std::string model = shippedModelPath();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(model, ec))
        return false;
    params.onnx.model = model;
    return true;
}

std::unique_ptr<Segmenter> makeSegmenter(const SegmentationParameters& params)
{
    if (params.backend == "none")
        return nullptr;
    core::LabelSet labels = loadLabelSet(params);
    std::unique_ptr<Segmenter> s;
    SegmentationParameters withModel = params;
    if (params.backend == "onnx" && !useShippedModelIfUnset(withModel))
        throw core::InputError("no [onnx] model configured and the shipped model " +
                               shippedModelPath() + " does not exist");
    if (params.backend == "onnx")
        s = std::make_unique<OnnxSegmenter>(withModel.onnx, std::move(labels));
    else
        s = std::make_unique<LabelImageSegmenter>(params.label_images, std::move(labels));
    if (params.crf.enabled)
        s = std::make_unique<CrfSegmenter>(std::move(s), params.crf);
    return s;
}
}  // namespace smap::segmentation
