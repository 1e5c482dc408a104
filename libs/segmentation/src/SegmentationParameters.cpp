#include "smap/segmentation/SegmentationParameters.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

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
    zoom.crops = cfg.read_int(s, "zoom_crops", zoom.crops);
    zoom.min_prior = cfg.read_double(s, "zoom_min_prior", zoom.min_prior);
    if (zoom.crops < 0 || zoom.crops > 8)
        throw core::InputError(mrpt::format(
            "[segmentation] zoom_crops = %d must be in [0, 8] (0 disables the zoom)", zoom.crops));
    if (!(zoom.min_prior >= 0.0 && zoom.min_prior <= 1.0))
        throw core::InputError(
            mrpt::format("[segmentation] zoom_min_prior = %g must be in [0, 1]", zoom.min_prior));
    onnx.loadFromConfigFile(cfg, "onnx");
    label_images.loadFromConfigFile(cfg, "label_images");
    crf.loadFromConfigFile(cfg, "crf");
}

void SegmentationParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                              const std::string&) const
{
    cfg.write("segmentation", "backend", backend);
    cfg.write("segmentation", "labels", labels);
    cfg.write("segmentation", "zoom_crops", zoom.crops);
    cfg.write("segmentation", "zoom_min_prior", zoom.min_prior);
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
    {
        s = std::make_unique<OnnxSegmenter>(withModel.onnx, std::move(labels));
        if (params.zoom.crops > 0)
            s = std::make_unique<ZoomSegmenter>(std::move(s), params.zoom);
    }
    else
        s = std::make_unique<LabelImageSegmenter>(params.label_images, std::move(labels));
    if (params.crf.enabled)
        s = std::make_unique<CrfSegmenter>(std::move(s), params.crf);
    return s;
}
}  // namespace smap::segmentation
