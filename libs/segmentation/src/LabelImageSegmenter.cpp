#include "smap/segmentation/LabelImageSegmenter.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "smap/core/InputError.h"

namespace fs = std::filesystem;

namespace smap::segmentation
{
void LabelImageParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                              const std::string&)
{
    const char* s = "label_images";
    folder = cfg.read_string(s, "folder", folder);
    match = cfg.read_string(s, "match", match);
    max_dt = cfg.read_double(s, "max_dt", max_dt);
    confidence = cfg.read_double(s, "confidence", confidence);
    confidence_folder = cfg.read_string(s, "confidence_folder", confidence_folder);
    if (match != "name" && match != "timestamp")
        throw core::InputError("[label_images] match = '" + match +
                               "' is not one of: name, timestamp");
    if (!(max_dt > 0.0))
        throw core::InputError(mrpt::format("[label_images] max_dt = %g must be > 0", max_dt));
    if (!(confidence > 0.0 && confidence <= 1.0))
        throw core::InputError(
            mrpt::format("[label_images] confidence = %g must be in (0, 1]", confidence));
}

void LabelImageParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                            const std::string&) const
{
    const char* s = "label_images";
    cfg.write(s, "folder", folder);
    cfg.write(s, "match", match);
    cfg.write(s, "max_dt", max_dt);
    cfg.write(s, "confidence", confidence);
    cfg.write(s, "confidence_folder", confidence_folder);
}

LabelImageSegmenter::LabelImageSegmenter(const LabelImageParameters& params, core::LabelSet labels)
    : Segmenter("LabelImageSegmenter", std::move(labels)), params_(params)
{
    if (params_.folder.empty())
        throw core::InputError("[label_images] folder is not set");
    if (!fs::is_directory(params_.folder))
        throw core::InputError("label image folder '" + params_.folder + "' does not exist");
    if (!params_.confidence_folder.empty() && !fs::is_directory(params_.confidence_folder))
        throw core::InputError("confidence folder '" + params_.confidence_folder +
                               "' does not exist");
    size_t pngs = 0;
    for (const auto& e : fs::directory_iterator(params_.folder))
    {
        if (e.path().extension() != ".png")
            continue;
        pngs++;
        if (params_.match != "timestamp")
            continue;
        const std::string stem = e.path().stem().string();
        char* end = nullptr;
        const double t = std::strtod(stem.c_str(), &end);
        if (end == stem.c_str() || *end != '\0' || !std::isfinite(t))
            throw core::InputError("label image '" + e.path().string() +
                                   "' is not named after a timestamp ([label_images] match = "
                                   "timestamp)");
        byTimestamp_[t] = e.path().string();
    }
    if (pngs == 0)
        throw core::InputError("label image folder '" + params_.folder + "' has no .png files");
}

std::string LabelImageSegmenter::fileFor(const core::RgbdFrame& frame) const
{
    if (params_.match == "name")
    {
        const fs::path p = fs::path(params_.folder) / (frame.name + ".png");
        return fs::exists(p) ? p.string() : std::string();
    }
    const auto after = byTimestamp_.lower_bound(frame.timestamp);
    std::string best;
    double bestDt = params_.max_dt;
    if (after != byTimestamp_.end() && std::abs(after->first - frame.timestamp) <= bestDt)
    {
        bestDt = std::abs(after->first - frame.timestamp);
        best = after->second;
    }
    if (after != byTimestamp_.begin())
    {
        const auto before = std::prev(after);
        if (std::abs(before->first - frame.timestamp) < bestDt ||
            (best.empty() && std::abs(before->first - frame.timestamp) <= bestDt))
            best = before->second;
    }
    return best;
}

SegmentationResult LabelImageSegmenter::segmentNative(const core::RgbdFrame& frame)
{
    const std::string path = fileFor(frame);
    if (path.empty())
        throw core::InputError(mrpt::format(
            "no label image for frame '%s' (t = %.6f) in '%s' ([label_images] match = %s)",
            frame.name.c_str(), frame.timestamp, params_.folder.c_str(), params_.match.c_str()));
    const cv::Mat labels = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (labels.empty() || labels.type() != CV_8UC1)
        throw core::InputError("label image '" + path +
                               "' is not a readable 8-bit single-channel image");
    if (!frame.colour.empty() &&
        std::abs(static_cast<double>(labels.cols) * frame.colour.rows -
                 static_cast<double>(labels.rows) * frame.colour.cols) > labels.rows)
        throw core::InputError(mrpt::format(
            "label image '%s' is %dx%d, not of the frame's aspect (%dx%d)", path.c_str(),
            labels.cols, labels.rows, frame.colour.cols, frame.colour.rows));
    cv::Mat confidence;
    if (!params_.confidence_folder.empty())
    {
        const std::string cpath =
            (fs::path(params_.confidence_folder) / fs::path(path).filename()).string();
        confidence = cv::imread(cpath, cv::IMREAD_UNCHANGED);
        if (confidence.empty() || confidence.type() != CV_8UC1 ||
            confidence.size() != labels.size())
            throw core::InputError(mrpt::format(
                "confidence image '%s' is missing, not 8-bit single-channel or not %dx%d",
                cpath.c_str(), labels.cols, labels.rows));
    }

    const int n = static_cast<int>(this->labels().size());
    const float uniform = 1.0f / static_cast<float>(n);
    cv::Mat probs(n, labels.rows * labels.cols, CV_32FC1);
    for (int v = 0; v < labels.rows; v++)
    {
        for (int u = 0; u < labels.cols; u++)
        {
            const int i = v * labels.cols + u;
            const int l = labels.at<uint8_t>(v, u);
            if (l == core::LabelSet::kVoid)
            {
                for (int k = 0; k < n; k++)
                    probs.at<float>(k, i) = uniform;
                continue;
            }
            if (l >= n)
                throw core::InputError(mrpt::format(
                    "label image '%s' has id %d at (%d, %d), outside the %d-class label set",
                    path.c_str(), l, u, v, n));
            float p = static_cast<float>(params_.confidence);
            if (!confidence.empty())
                p = std::max(uniform, confidence.at<uint8_t>(v, u) / 255.0f);
            const float rest = n > 1 ? (1.0f - p) / static_cast<float>(n - 1) : 0.0f;
            for (int k = 0; k < n; k++)
                probs.at<float>(k, i) = k == l ? p : rest;
        }
    }
    auto r = SegmentationResult::fromProbabilities(probs, labels.cols, labels.rows);
    // Ties (a void pixel) would take label 0 by arg max: keep the image's labels instead.
    r.labels = labels.clone();
    return r;
}

std::string LabelImageSegmenter::description() const
{
    return "label images from " + params_.folder + " (by " + params_.match + ")";
}
}  // namespace smap::segmentation
