#include "smap/segmentation/LabelImageSegmenter.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

namespace fs = std::filesystem;

namespace smap::segmentation
{
core::OptionFields LabelImageParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "label_images");
    f.add("folder", folder)
        .add("match", match)
        .add("max_dt", max_dt)
        .add("confidence", confidence)
        .add("confidence_folder", confidence_folder)
        .add("kind", kind);
    return f;
}

void LabelImageParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                              const std::string& section)
{
    fields(section).load(cfg);
    if (kind != "labels" && kind != "probabilities")
        throw core::InputError("[label_images] kind = '" + kind +
                               "' is not one of: labels, probabilities");
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
                                            const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<LabelImageParameters*>(this)->fields(section).save(cfg);
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
    extension_ = params_.kind == "labels" ? ".png" : ".tiff";
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(params_.folder))
    {
        if (e.path().extension() != extension_)
            continue;
        files++;
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
    if (files == 0)
        throw core::InputError("label image folder '" + params_.folder + "' has no " + extension_ +
                               " files ([label_images] kind = " + params_.kind + ")");
}

std::string LabelImageSegmenter::fileFor(const core::RgbdFrame& frame) const
{
    if (params_.match == "name")
    {
        const fs::path p = fs::path(params_.folder) / (frame.name + extension_);
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
    if (params_.kind == "probabilities")
        return readProbabilities(path, frame);
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

SegmentationResult LabelImageSegmenter::readProbabilities(const std::string& path,
                                                          const core::RgbdFrame& frame) const
{
    std::vector<cv::Mat> pages;
    const int n = static_cast<int>(labels().size());
    if (!cv::imreadmulti(path, pages, cv::IMREAD_UNCHANGED) || static_cast<int>(pages.size()) != n)
        throw core::InputError(mrpt::format(
            "probability image '%s' must be a multi-page TIFF with one page per class (%d), "
            "not %zu",
            path.c_str(), n, pages.size()));
    const cv::Size size = pages[0].size();
    if (!frame.colour.empty() &&
        std::abs(static_cast<double>(size.width) * frame.colour.rows -
                 static_cast<double>(size.height) * frame.colour.cols) > size.height)
        throw core::InputError(mrpt::format(
            "probability image '%s' is %dx%d, not of the frame's "
            "aspect (%dx%d)",
            path.c_str(), size.width, size.height, frame.colour.cols, frame.colour.rows));
    cv::Mat probs(n, size.area(), CV_32FC1);
    for (int k = 0; k < n; k++)
    {
        const cv::Mat& page = pages[static_cast<size_t>(k)];
        const int depth = page.depth();
        if (page.size() != size || page.channels() != 1 ||
            (depth != CV_8U && depth != CV_16U && depth != CV_32F))
            throw core::InputError(mrpt::format(
                "probability image '%s': page %d is not single-channel 8-bit, 16-bit or float "
                "of %dx%d",
                path.c_str(), k, size.width, size.height));
        // 8- and 16-bit pages hold probability x the type's maximum.
        const double scale = depth == CV_8U ? 1.0 / 255.0 : depth == CV_16U ? 1.0 / 65535.0 : 1.0;
        cv::Mat row = probs.row(k).reshape(1, size.height);
        page.convertTo(row, CV_32F, scale);
    }
    // Columns to distributions (all-zero columns: uniform).
    cv::Mat sum;
    cv::reduce(probs, sum, 0, cv::REDUCE_SUM);
    for (int i = 0; i < probs.cols; i++)
    {
        const float t = sum.at<float>(i);
        for (int k = 0; k < n; k++)
        {
            float& v = probs.at<float>(k, i);
            v = t > 0.0f ? v / t : 1.0f / static_cast<float>(n);
        }
    }
    return SegmentationResult::fromProbabilities(probs, size.width, size.height);
}

std::string LabelImageSegmenter::description() const
{
    return (params_.kind == "labels" ? "label images from " : "probability images from ") +
           params_.folder + " (by " + params_.match + ")";
}
}  // namespace smap::segmentation
