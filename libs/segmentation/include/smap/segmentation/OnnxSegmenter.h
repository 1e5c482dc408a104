// A CNN segmenter on OpenCV's dnn module: any ONNX model with a 1 x C x H x W score output
// (e.g. ESPNetv2 on PASCAL VOC, ../shared/models/espnetv2-voc). cv::dnn stays in the .cpp.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <utility>
#include <vector>

#include "smap/segmentation/Segmenter.h"

namespace smap::segmentation
{
/// [onnx] section.
struct OnnxSegmenterParameters : public mrpt::config::CLoadableOptions
{
    /// Path of the .onnx file (relative paths from the working directory).
    std::string model;
    /// The network's input size; frames are resized to it (INTER_AREA when shrinking).
    int input_width = 320;
    int input_height = 240;
    /// Channel order the network expects: true = RGB (ESPNetv2), false = BGR.
    bool rgb = true;
    /// Pre-processing per channel, in the network's channel order: (pixel x scale - mean) / std.
    double scale = 1.0 / 255.0;
    cv::Vec3d mean{0.485, 0.456, 0.406};
    cv::Vec3d std{0.229, 0.224, 0.225};
    /// The model's output classes in order (default: the 21 PASCAL VOC classes).
    std::vector<std::string> classes;
    /// "model_class:label" pairs for model classes whose name is not in the label set (their
    /// probabilities are added to that label's); "model_class:void" drops a class.
    std::vector<std::pair<std::string, std::string>> class_map;
    /// Worker threads of OpenCV's parallel framework (process-wide: cv::setNumThreads, set
    /// once when the segmenter is created); 0 = leave it as it is.
    int threads = 2;

    OnnxSegmenterParameters();
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
};

class OnnxSegmenter : public Segmenter
{
public:
    /// Loads the model and runs it once on a blank image to check its output against
    /// `classes`. Throws core::InputError naming the file for a missing or malformed model, a
    /// class that maps nowhere, or an output shape that does not match the class list.
    OnnxSegmenter(const OnnxSegmenterParameters& params, core::LabelSet labels);
    ~OnnxSegmenter() override;

    SegmentationResult segmentNative(const core::RgbdFrame& frame) override;
    std::string description() const override;

    /// The network input for a BGR image: resized, channel order, scale, mean and std, NCHW.
    cv::Mat inputBlob(const cv::Mat& bgr) const;
    /// The network's raw output for a BGR image (1 x C x H x W scores, a copy).
    cv::Mat forward(const cv::Mat& bgr);
    /// The raw output's C x (H*W) scores turned into probabilities over the label set (in
    /// place: pass a copy to keep the scores).
    cv::Mat toLabelProbabilities(cv::Mat output) const;

    const OnnxSegmenterParameters& parameters() const { return params_; }

private:
    struct Impl;
    OnnxSegmenterParameters params_;
    std::unique_ptr<Impl> impl_;
    /// For each model class, its label id, or -1 when dropped.
    std::vector<int> classToLabel_;
    bool identityMapping_ = false;
};
}  // namespace smap::segmentation
