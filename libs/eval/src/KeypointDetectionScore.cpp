#include "smap/eval/KeypointDetectionScore.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include "smap/core/InputError.h"

namespace smap::eval
{
void KeypointDetectionScore::add(bool truth, bool said)
{
    if (truth)
        (said ? truePositives : falseNegatives)++;
    else
        (said ? falsePositives : trueNegatives)++;
}

KeypointDetectionScore& KeypointDetectionScore::operator+=(const KeypointDetectionScore& o)
{
    truePositives += o.truePositives;
    falsePositives += o.falsePositives;
    falseNegatives += o.falseNegatives;
    trueNegatives += o.trueNegatives;
    frames += o.frames;
    nearEdge += o.nearEdge;
    maskOffBand += o.maskOffBand;
    for (size_t k = 0; k < falsePositivesByDistance.size(); ++k)
        falsePositivesByDistance[k] += o.falsePositivesByDistance[k];
    for (size_t k = 0; k < falsePositivesByEvidence.size(); ++k)
        falsePositivesByEvidence[k] += o.falsePositivesByEvidence[k];
    for (auto [mine, theirs] :
         {std::pair{&bandOnMask, &o.bandOnMask}, std::pair{&bandBesideMask, &o.bandBesideMask}})
    {
        mine->keypoints += theirs->keypoints;
        mine->said += theirs->said;
    }
    return *this;
}

double KeypointDetectionScore::BandSide::saidFraction() const
{
    return keypoints == 0 ? 0.0 : static_cast<double>(said) / static_cast<double>(keypoints);
}

double KeypointDetectionScore::recall() const
{
    const size_t n = truePositives + falseNegatives;
    return n == 0 ? 1.0 : static_cast<double>(truePositives) / static_cast<double>(n);
}

double KeypointDetectionScore::precision() const
{
    const size_t n = truePositives + falsePositives;
    return n == 0 ? 1.0 : static_cast<double>(truePositives) / static_cast<double>(n);
}

double KeypointDetectionScore::precisionWithin(double px) const
{
    size_t kept = 0;
    for (size_t k = 0; k < kDistanceBands.size() && kDistanceBands[k] <= px; ++k)
        kept += falsePositivesByDistance[k];
    const size_t n = truePositives + kept;
    return n == 0 ? 1.0 : static_cast<double>(truePositives) / static_cast<double>(n);
}

double KeypointDetectionScore::bestPrecisionAtRecall(double recall) const
{
    const auto offBand = static_cast<double>(maskOffBand);
    const auto onBand = static_cast<double>(bandOnMask.keypoints);
    const auto besideBand = static_cast<double>(bandBesideMask.keypoints);
    const double needed = recall * (offBand + onBand) - offBand;
    if (needed <= 0.0 || onBand == 0.0)
        return 1.0;
    const double rate = std::min(1.0, needed / onBand);
    const double said = offBand + rate * onBand;
    return said / (said + rate * besideBand);
}

core::JsonValue KeypointDetectionScore::toJson() const
{
    auto j = core::JsonValue::object();
    j.set("frames", static_cast<double>(frames))
        .set("true_positives", static_cast<double>(truePositives))
        .set("false_positives", static_cast<double>(falsePositives))
        .set("false_negatives", static_cast<double>(falseNegatives))
        .set("true_negatives", static_cast<double>(trueNegatives));
    j.set("left_out_near_mask_edges", static_cast<double>(nearEdge));
    j.set("recall", recall()).set("precision", precision());
    auto byDistance = core::JsonValue::object();
    for (size_t k = 0; k < falsePositivesByDistance.size(); ++k)
        byDistance.set(k < kDistanceBands.size() ? mrpt::format("up_to_%g_px", kDistanceBands[k])
                                                 : std::string("farther"),
                       static_cast<double>(falsePositivesByDistance[k]));
    j.set("false_positives_by_distance", std::move(byDistance));
    auto byEvidence = core::JsonValue::object();
    const char* names[] = {"flow", "depth", "region", "semantic_only", "other"};
    for (size_t k = 0; k < falsePositivesByEvidence.size(); ++k)
        byEvidence.set(names[k], static_cast<double>(falsePositivesByEvidence[k]));
    j.set("false_positives_by_evidence", std::move(byEvidence));
    j.set("precision_within_3_px", precisionWithin(3.0));
    auto band = core::JsonValue::object();
    band.set("width_px", static_cast<double>(kOutlineBandPx))
        .set("on_mask_keypoints", static_cast<double>(bandOnMask.keypoints))
        .set("on_mask_said_dynamic", static_cast<double>(bandOnMask.said))
        .set("beside_mask_keypoints", static_cast<double>(bandBesideMask.keypoints))
        .set("beside_mask_said_dynamic", static_cast<double>(bandBesideMask.said))
        .set("mask_keypoints_off_band", static_cast<double>(maskOffBand))
        .set(mrpt::format("best_precision_at_recall_%g", kTargetRecall),
             bestPrecisionAtRecall(kTargetRecall));
    j.set("outline_band", std::move(band));
    return j;
}

namespace
{
using Evidence = KeypointDetectionScore::Evidence;

/// The columns of an evidence table that say why a keypoint was decided dynamic (-1: absent).
struct EvidenceColumns
{
    int flow = -1, depth = -1, region = -1, semantic = -1;

    explicit EvidenceColumns(const std::string& header)
    {
        std::stringstream ss(header);
        std::string name;
        for (int i = 0; std::getline(ss, name, ','); ++i)
        {
            if (name == "flow")
                flow = i;
            else if (name == "depth_test")
                depth = i;
            else if (name == "region")
                region = i;
            else if (name == "semantic")
                semantic = i;
        }
    }

    Evidence of(const std::vector<std::string>& cells) const
    {
        const auto set = [&](int c)
        { return c >= 0 && static_cast<size_t>(c) < cells.size() && cells[c] == "1"; };
        if (set(flow))
            return Evidence::Flow;
        if (set(depth))
            return Evidence::Depth;
        if (set(region))
            return Evidence::Region;
        return set(semantic) ? Evidence::SemanticOnly : Evidence::Other;
    }
};

/// The pixels within `px` of a mask edge: those whose (2 px + 1) square holds both mask and
/// non-mask pixels (the dilated and eroded masks differ there).
cv::Mat nearMaskEdge(const cv::Mat& mask, int px)
{
    const cv::Mat binary = mask != 0;
    const cv::Mat box = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * px + 1, 2 * px + 1));
    cv::Mat grown, shrunk;
    cv::dilate(binary, grown, box, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
    cv::erode(binary, shrunk, box, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
    return grown != shrunk;
}

/// Counts a false positive at pixel (x, y) by its distance from the mask and by its evidence.
void countFalsePositive(KeypointDetectionScore& score, const cv::Mat& distance, int x, int y,
                        Evidence evidence)
{
    const auto d = static_cast<double>(distance.at<float>(y, x));
    size_t band = 0;
    while (band < KeypointDetectionScore::kDistanceBands.size() &&
           d > KeypointDetectionScore::kDistanceBands[band])
        band++;
    score.falsePositivesByDistance[band]++;
    score.falsePositivesByEvidence[static_cast<size_t>(evidence)]++;
}
/// One keypoint of an evidence table: its pixel, the table's decision and why.
struct TableRow
{
    int x = 0, y = 0;
    bool said = false;
    Evidence evidence = Evidence::Other;
};

TableRow parseRow(const std::string& line, size_t row, const EvidenceColumns& columns,
                  const std::string& evidence_csv, const cv::Mat& mask, const std::string& mask_png)
{
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');)
        cells.push_back(c);
    char* end = nullptr;
    const double u = cells.size() >= 3 ? std::strtod(cells[0].c_str(), &end) : -1.0;
    const double v = cells.size() >= 3 ? std::strtod(cells[1].c_str(), &end) : -1.0;
    const long x = std::lround(u), y = std::lround(v);
    if (cells.size() < 3 || x < 0 || y < 0 || x >= mask.cols || y >= mask.rows ||
        (cells.back() != "0" && cells.back() != "1"))
        throw core::InputError(mrpt::format(
            "'%s' line %zu: '%s' is not a keypoint inside the %dx%d mask '%s'",
            evidence_csv.c_str(), row, line.c_str(), mask.cols, mask.rows, mask_png.c_str()));
    return {static_cast<int>(x), static_cast<int>(y), cells.back() == "1", columns.of(cells)};
}

cv::Mat readEightBit(const std::string& png, const char* what)
{
    cv::Mat image = cv::imread(png, cv::IMREAD_UNCHANGED);
    if (image.empty() || image.type() != CV_8UC1)
        throw core::InputError(
            mrpt::format("'%s' is not an 8-bit single-channel %s", png.c_str(), what));
    return image;
}

/// The pixels where a label image says dynamic (one of `said`), for decisions by labels.
cv::Mat saidByLabels(const KeypointScoreOptions& o, const cv::Mat& mask,
                     const std::string& mask_png)
{
    if (o.decision == KeypointDecision::Table)
        return {};
    const cv::Mat labels = readEightBit(o.labelPng, "label image");
    if (labels.size() != mask.size())
        throw core::InputError(mrpt::format("label image '%s' is %dx%d but the mask '%s' is %dx%d",
                                            o.labelPng.c_str(), labels.cols, labels.rows,
                                            mask_png.c_str(), mask.cols, mask.rows));
    cv::Mat said(labels.size(), CV_8UC1, cv::Scalar(0));
    for (const int id : o.saidLabels)
        said.setTo(255, labels == id);
    return said;
}

/// Adds one keypoint's outcome: the outline band's sides, the edge margin, the score and
/// where its false positive lies.
void scoreKeypoint(KeypointDetectionScore& score, const TableRow& k, bool truth, bool inBand,
                   bool nearEdge, const cv::Mat& mask, cv::Mat& distance)
{
    if (inBand)
    {
        auto& side = truth ? score.bandOnMask : score.bandBesideMask;
        side.keypoints++;
        side.said += k.said ? 1 : 0;
    }
    else if (truth)
    {
        score.maskOffBand++;
    }
    if (nearEdge)
    {
        score.nearEdge++;
        return;
    }
    score.add(truth, k.said);
    if (truth || !k.said)
        return;
    // Distance (px) of each pixel from the nearest mask pixel (0 on the mask), computed at the
    // frame's first false positive.
    if (distance.empty())
        cv::distanceTransform(mask == 0, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    countFalsePositive(score, distance, k.x, k.y, k.evidence);
}
}  // namespace

KeypointDetectionScore scoreKeypointFrame(const std::string& evidence_csv,
                                          const std::string& mask_png,
                                          const KeypointScoreOptions& options)
{
    if (options.edgeMargin < 0)
        throw core::InputError(mrpt::format("edge margin %d must be >= 0", options.edgeMargin));
    std::ifstream in(evidence_csv);
    if (!in)
        throw core::InputError("cannot read keypoint evidence '" + evidence_csv + "'");
    std::string line;
    KeypointDetectionScore score;
    if (!std::getline(in, line) || line.rfind("# not evaluated", 0) == 0)
        return score;
    if (line.rfind("u,v,", 0) != 0)
        throw core::InputError(mrpt::format("'%s': first line '%s' is not the evidence header",
                                            evidence_csv.c_str(), line.c_str()));
    const cv::Mat mask = readEightBit(mask_png, "mask");
    const cv::Mat band = nearMaskEdge(mask, KeypointDetectionScore::kOutlineBandPx);
    cv::Mat nearEdge;
    if (options.edgeMargin > 0)
        nearEdge = options.edgeMargin == KeypointDetectionScore::kOutlineBandPx
                       ? band
                       : nearMaskEdge(mask, options.edgeMargin);
    const cv::Mat saidByLabel = saidByLabels(options, mask, mask_png);
    const EvidenceColumns columns(line);
    cv::Mat distance;
    score.frames = 1;
    for (size_t row = 2; std::getline(in, line); ++row)
    {
        TableRow k = parseRow(line, row, columns, evidence_csv, mask, mask_png);
        const bool inBand = band.at<uint8_t>(k.y, k.x) != 0;
        if (options.decision == KeypointDecision::Labels ||
            (options.decision == KeypointDecision::LabelsInBand && inBand))
        {
            k.said = saidByLabel.at<uint8_t>(k.y, k.x) != 0;
            k.evidence = Evidence::Other;
        }
        scoreKeypoint(score, k, mask.at<uint8_t>(k.y, k.x) != 0, inBand,
                      !nearEdge.empty() && nearEdge.at<uint8_t>(k.y, k.x) != 0, mask, distance);
    }
    return score;
}
}  // namespace smap::eval
