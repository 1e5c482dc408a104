#include "smap/eval/SegmentationScore.h"

#include <mrpt/core/format.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace smap::eval
{
namespace
{
double ratio(double num, double den)
{
    return den > 0.0 ? num / den : std::nan("");
}
}  // namespace

double ClassSegmentationScore::fpr() const
{
    return ratio(static_cast<double>(fp), static_cast<double>(fp + tn));
}
double ClassSegmentationScore::fnr() const
{
    return ratio(static_cast<double>(fn), static_cast<double>(tp + fn));
}
double ClassSegmentationScore::recall() const
{
    return ratio(static_cast<double>(tp), static_cast<double>(tp + fn));
}
double ClassSegmentationScore::precision() const
{
    return ratio(static_cast<double>(tp), static_cast<double>(tp + fp));
}
double ClassSegmentationScore::pwc() const
{
    return ratio(static_cast<double>(fn + fp), static_cast<double>(tp + fn + fp + tn));
}
double ClassSegmentationScore::iou() const
{
    return ratio(intersection, unionArea);
}
double ClassSegmentationScore::bandIou() const
{
    return ratio(bandIntersection, bandUnion);
}

SegmentationScore::SegmentationScore(const std::vector<std::pair<int, std::string>>& classes,
                                     SegmentationScoreOptions options)
    : options_(options)
{
    for (const auto& [id, name] : classes)
    {
        ClassSegmentationScore c;
        c.id = id;
        c.name = name;
        classes_.push_back(std::move(c));
    }
}

void SegmentationScore::addFrame(const cv::Mat& truth, const cv::Mat& predicted)
{
    if (truth.type() != CV_8UC1 || predicted.type() != CV_8UC1 || truth.size() != predicted.size())
        throw std::invalid_argument(mrpt::format(
            "segmentation score: label images must be 8-bit single-channel of one size "
            "(truth %dx%d, predicted %dx%d)",
            truth.cols, truth.rows, predicted.cols, predicted.rows));
    frames_++;
    cv::Mat valid(truth.size(), CV_8UC1, cv::Scalar(255));
    if (options_.voidLabel >= 0)
        valid = truth != options_.voidLabel;
    const double minArea = std::max(1.0, options_.minAreaFraction * cv::countNonZero(valid));
    const int r = options_.bandRadius;
    const cv::Mat disc =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
    for (auto& c : classes_)
    {
        const cv::Mat gt = (truth == c.id) & valid;
        const cv::Mat pr = (predicted == c.id) & valid;
        const double inter = cv::countNonZero(gt & pr);
        const double uni = cv::countNonZero(gt | pr);
        c.intersection += inter;
        c.unionArea += uni;
        const bool present = cv::countNonZero(gt) >= minArea;
        const bool said = cv::countNonZero(pr) >= minArea;
        if (present)
        {
            (uni > 0.0 && inter / uni >= options_.iouThreshold ? c.tp : c.fn)++;
            if (r > 0)
            {
                cv::Mat grown, shrunk;
                cv::dilate(gt, grown, disc);
                cv::erode(gt, shrunk, disc, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
                const cv::Mat band = grown & ~shrunk & valid;
                c.bandIntersection += cv::countNonZero(gt & pr & band);
                c.bandUnion += cv::countNonZero((gt | pr) & band);
            }
        }
        else
        {
            (said ? c.fp : c.tn)++;
        }
    }
}

std::string SegmentationScore::toText() const
{
    std::string s = mrpt::format(
        "%zu frames; correctly segmented = IoU >= %.2f; present/predicted = area >= %.2f%% of "
        "the scored pixels; band IoU within %d px of true edges\n",
        frames_, options_.iouThreshold, 100.0 * options_.minAreaFraction, options_.bandRadius);
    s += mrpt::format("%-12s %7s %5s %5s %5s %5s %6s %6s %6s %6s %6s %6s %8s\n", "class", "present",
                      "TP", "FN", "FP", "TN", "FPR", "FNR", "Re", "Pr", "PWC", "IoU", "bandIoU");
    for (const auto& c : classes_)
        s += mrpt::format(
            "%-12s %7zu %5zu %5zu %5zu %5zu %6.3f %6.3f %6.3f %6.3f %6.3f %6.3f %8.3f\n",
            c.name.c_str(), c.tp + c.fn, c.tp, c.fn, c.fp, c.tn, c.fpr(), c.fnr(), c.recall(),
            c.precision(), c.pwc(), c.iou(), c.bandIou());
    return s;
}

core::JsonValue SegmentationScore::toJson() const
{
    // NaN (a ratio with nothing to count) is written as null.
    auto num = [](double v) { return core::JsonValue::number(v); };
    auto j = core::JsonValue::object();
    j.set("frames", static_cast<uint64_t>(frames_))
        .set("iou_threshold", options_.iouThreshold)
        .set("min_area_fraction", options_.minAreaFraction)
        .set("void_label", options_.voidLabel)
        .set("band_radius_px", options_.bandRadius);
    auto arr = core::JsonValue::array();
    for (const auto& c : classes_)
    {
        auto o = core::JsonValue::object();
        o.set("id", c.id)
            .set("name", c.name)
            .set("tp", static_cast<uint64_t>(c.tp))
            .set("fn", static_cast<uint64_t>(c.fn))
            .set("fp", static_cast<uint64_t>(c.fp))
            .set("tn", static_cast<uint64_t>(c.tn))
            .set("fpr", num(c.fpr()))
            .set("fnr", num(c.fnr()))
            .set("recall", num(c.recall()))
            .set("precision", num(c.precision()))
            .set("pwc", num(c.pwc()))
            .set("iou", num(c.iou()))
            .set("band_iou", num(c.bandIou()));
        arr.push(std::move(o));
    }
    j.set("classes", std::move(arr));
    return j;
}
}  // namespace smap::eval
