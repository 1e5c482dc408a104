#include "smap/segmentation/OnnxSegmenter.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "smap/core/InputError.h"

namespace smap::segmentation
{
namespace
{
std::vector<std::string> splitList(const std::string& s, char sep)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, sep))
    {
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t\r") + 1);
        if (!item.empty())
            out.push_back(item);
    }
    return out;
}

std::string joinList(const std::vector<std::string>& v, const char* sep)
{
    std::string s;
    for (const auto& x : v)
        s += (s.empty() ? "" : sep) + x;
    return s;
}

cv::Vec3d readTriple(const mrpt::config::CConfigFileBase& cfg, const char* key,
                     const cv::Vec3d& def)
{
    const std::string text =
        cfg.read_string("onnx", key, mrpt::format("%.17g %.17g %.17g", def[0], def[1], def[2]));
    std::stringstream ss(text);
    cv::Vec3d v;
    std::string extra;
    if (!(ss >> v[0] >> v[1] >> v[2]) || (ss >> extra))
        throw core::InputError(
            mrpt::format("[onnx] %s = '%s' must be three numbers", key, text.c_str()));
    return v;
}

std::string shapeText(const cv::Mat& m)
{
    std::string s;
    for (int i = 0; i < m.dims; i++)
        s += (i ? "x" : "") + std::to_string(m.size[i]);
    return s;
}
}  // namespace

OnnxSegmenterParameters::OnnxSegmenterParameters()
{
    const core::LabelSet voc = core::LabelSet::pascalVoc();
    for (const auto& l : voc.labels())
        classes.push_back(l.name);
}

void OnnxSegmenterParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                 const std::string&)
{
    const char* s = "onnx";
    model = cfg.read_string(s, "model", model);
    input_width = cfg.read_int(s, "input_width", input_width);
    input_height = cfg.read_int(s, "input_height", input_height);
    rgb = cfg.read_bool(s, "rgb", rgb);
    scale = cfg.read_double(s, "scale", scale);
    mean = readTriple(cfg, "mean", mean);
    std = readTriple(cfg, "std", std);
    classes = splitList(cfg.read_string(s, "classes", joinList(classes, ",")), ',');
    std::vector<std::string> mapText;
    for (const auto& [from, to] : class_map)
    {
        mapText.push_back(from);
        mapText.back() += ":" + to;
    }
    class_map.clear();
    for (const auto& pair : splitList(cfg.read_string(s, "class_map", joinList(mapText, ",")), ','))
    {
        const auto parts = splitList(pair, ':');
        if (parts.size() != 2)
            throw core::InputError("[onnx] class_map entry '" + pair +
                                   "' must be model_class:label");
        class_map.emplace_back(parts[0], parts[1]);
    }
    threads = cfg.read_int(s, "threads", threads);
    if (input_width < 16 || input_height < 16 || input_width > 8192 || input_height > 8192)
        throw core::InputError(mrpt::format("[onnx] input size %dx%d must be within 16-8192",
                                            input_width, input_height));
    if (!(scale > 0.0) || !(std[0] > 0.0 && std[1] > 0.0 && std[2] > 0.0))
        throw core::InputError("[onnx] scale and every std value must be > 0");
    if (classes.empty())
        throw core::InputError("[onnx] classes must list the model's output classes");
    if (threads < 0 || threads > 256)
        throw core::InputError(mrpt::format("[onnx] threads = %d must be in [0, 256]", threads));
}

void OnnxSegmenterParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                               const std::string&) const
{
    const char* s = "onnx";
    cfg.write(s, "model", model);
    cfg.write(s, "input_width", input_width);
    cfg.write(s, "input_height", input_height);
    cfg.write(s, "rgb", rgb);
    cfg.write(s, "scale", mrpt::format("%.17g", scale));
    cfg.write(s, "mean", mrpt::format("%.17g %.17g %.17g", mean[0], mean[1], mean[2]));
    cfg.write(s, "std", mrpt::format("%.17g %.17g %.17g", std[0], std[1], std[2]));
    cfg.write(s, "classes", joinList(classes, ","));
    std::vector<std::string> mapText;
    for (const auto& [from, to] : class_map)
    {
        mapText.push_back(from);
        mapText.back() += ":" + to;
    }
    cfg.write(s, "class_map", joinList(mapText, ","));
    cfg.write(s, "threads", threads);
}

struct OnnxSegmenter::Impl
{
    cv::dnn::Net net;
};

OnnxSegmenter::OnnxSegmenter(const OnnxSegmenterParameters& params, core::LabelSet labels)
    : Segmenter("OnnxSegmenter", std::move(labels)), params_(params), impl_(new Impl)
{
    const std::string& path = params_.model;
    if (path.empty())
        throw core::InputError("[onnx] model is not set: give the path of an .onnx file");
    // Process-wide, and so only here: changing it while other threads run OpenCV's parallel
    // loops crashes OpenCV's TBB back end.
    if (params_.threads > 0)
        cv::setNumThreads(params_.threads);
    if (!std::filesystem::is_regular_file(path))
        throw core::InputError("ONNX model '" + path + "' does not exist or is not a file");

    // Each model class goes to the label of the same name, or where class_map sends it.
    for (const auto& name : params_.classes)
    {
        std::string target = name;
        for (const auto& [from, to] : params_.class_map)
            if (from == name)
                target = to;
        if (target == "void")
        {
            classToLabel_.push_back(-1);
            continue;
        }
        const auto id = this->labels().find(target);
        if (!id)
            throw core::InputError(mrpt::format(
                "ONNX model '%s': class '%s' is not in the label set; map it with [onnx] "
                "class_map (model_class:label, or model_class:void)",
                path.c_str(), name.c_str()));
        classToLabel_.push_back(*id);
    }
    identityMapping_ = classToLabel_.size() == this->labels().size();
    for (size_t i = 0; identityMapping_ && i < classToLabel_.size(); i++)
        identityMapping_ = classToLabel_[i] == static_cast<int>(i);

    try
    {
        impl_->net = cv::dnn::readNetFromONNX(path);
    }
    catch (const cv::Exception& e)
    {
        throw core::InputError("cannot load ONNX model '" + path + "': " + e.err);
    }
    if (impl_->net.empty())
        throw core::InputError("ONNX model '" + path + "' has no layers");
    impl_->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    impl_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);

    // A dry run checks the output against the class list now rather than on the first keyframe.
    cv::Mat out;
    try
    {
        out = forward(
            cv::Mat(params_.input_height, params_.input_width, CV_8UC3, cv::Scalar::all(128)));
    }
    catch (const cv::Exception& e)
    {
        throw core::InputError(mrpt::format(
            "ONNX model '%s' does not run on a 1x3x%dx%d input ([onnx] input_width/height): %s",
            path.c_str(), params_.input_height, params_.input_width, e.err.c_str()));
    }
    if (out.dims != 4 || out.size[0] != 1 ||
        out.size[1] != static_cast<int>(params_.classes.size()))
        throw core::InputError(mrpt::format(
            "ONNX model '%s': output shape %s does not match 1 x %zu x H x W (the %zu classes "
            "of [onnx] classes)",
            path.c_str(), shapeText(out).c_str(), params_.classes.size(), params_.classes.size()));
    MRPT_LOG_INFO_FMT("loaded %s: input 1x3x%dx%d, output %s", path.c_str(), params_.input_height,
                      params_.input_width, shapeText(out).c_str());
}

OnnxSegmenter::~OnnxSegmenter() = default;

cv::Mat OnnxSegmenter::inputBlob(const cv::Mat& bgr) const
{
    CV_Assert(bgr.type() == CV_8UC3 && !bgr.empty());
    const cv::Size size(params_.input_width, params_.input_height);
    cv::Mat resized;
    if (bgr.size() == size)
        resized = bgr;
    else
        cv::resize(bgr, resized, size, 0, 0,
                   bgr.cols > size.width ? cv::INTER_AREA : cv::INTER_LINEAR);
    cv::Mat ordered;
    if (params_.rgb)
        cv::cvtColor(resized, ordered, cv::COLOR_BGR2RGB);
    else
        ordered = resized;
    cv::Mat f;
    ordered.convertTo(f, CV_32FC3, params_.scale);
    cv::subtract(f, cv::Scalar(params_.mean[0], params_.mean[1], params_.mean[2]), f);
    cv::divide(f, cv::Scalar(params_.std[0], params_.std[1], params_.std[2]), f);
    return cv::dnn::blobFromImage(f);
}

cv::Mat OnnxSegmenter::forward(const cv::Mat& bgr)
{
    impl_->net.setInput(inputBlob(bgr));
    return impl_->net.forward().clone();
}

cv::Mat OnnxSegmenter::toLabelProbabilities(cv::Mat output) const
{
    CV_Assert(output.dims == 4 && output.isContinuous());
    const int c = output.size[1], pixels = output.size[2] * output.size[3];
    const int shape[2] = {c, pixels};
    cv::Mat scores = output.reshape(1, 2, shape);  // shares (and keeps) output's buffer
    softmaxColumns(scores);
    if (identityMapping_)
        return scores;
    cv::Mat probs(static_cast<int>(labels().size()), pixels, CV_32FC1, cv::Scalar(0));
    for (int i = 0; i < c; i++)
        if (classToLabel_[i] >= 0)
            probs.row(classToLabel_[i]) += scores.row(i);
    // Dropped classes take their share away: renormalise (a floor keeps empty columns finite).
    cv::Mat sum;
    cv::reduce(probs, sum, 0, cv::REDUCE_SUM);
    cv::max(sum, 1e-12, sum);
    for (int k = 0; k < probs.rows; k++)
        cv::divide(probs.row(k), sum, probs.row(k));
    return probs;
}

SegmentationResult OnnxSegmenter::segmentNative(const core::RgbdFrame& frame)
{
    if (frame.colour.type() != CV_8UC3 || frame.colour.empty())
        throw core::InputError("frame '" + frame.name + "' has no BGR colour image to segment");
    const cv::Mat out = forward(frame.colour);
    return SegmentationResult::fromProbabilities(toLabelProbabilities(out), out.size[3],
                                                 out.size[2]);
}

std::string OnnxSegmenter::description() const
{
    return mrpt::format("onnx %s %dx%d",
                        std::filesystem::path(params_.model).filename().string().c_str(),
                        params_.input_width, params_.input_height);
}
}  // namespace smap::segmentation
