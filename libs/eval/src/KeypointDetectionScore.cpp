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
    const double truePositives = offBand + rate * onBand;
    return truePositives / (truePositives + rate * besideBand);
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
}  // namespace

KeypointDetectionScore scoreKeypointFrame(const std::string& evidence_csv,
                                          const std::string& mask_png, int edge_margin)
{
    if (edge_margin < 0)
        throw core::InputError(mrpt::format("edge margin %d must be >= 0", edge_margin));
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
    const cv::Mat mask = cv::imread(mask_png, cv::IMREAD_UNCHANGED);
    if (mask.empty() || mask.type() != CV_8UC1)
        throw core::InputError("'" + mask_png + "' is not an 8-bit single-channel mask");
    const cv::Mat band = nearMaskEdge(mask, KeypointDetectionScore::kOutlineBandPx);
    cv::Mat nearEdge;
    if (edge_margin > 0)
        nearEdge = edge_margin == KeypointDetectionScore::kOutlineBandPx
                       ? band
                       : nearMaskEdge(mask, edge_margin);
    const EvidenceColumns columns(line);
    // Distance (px) of each pixel from the nearest mask pixel (0 on the mask), computed at the
    // frame's first false positive.
    cv::Mat distance;
    score.frames = 1;
    size_t row = 1;
    while (std::getline(in, line))
    {
        row++;
        std::vector<std::string> cells;
        std::stringstream ss(line);
        std::string c;
        while (std::getline(ss, c, ','))
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
        const int px = static_cast<int>(x), py = static_cast<int>(y);
        const bool said = cells.back() == "1";
        const bool truth = mask.at<uint8_t>(py, px) != 0;
        if (band.at<uint8_t>(py, px))
        {
            auto& side = truth ? score.bandOnMask : score.bandBesideMask;
            side.keypoints++;
            side.said += said ? 1 : 0;
        }
        else if (truth)
        {
            score.maskOffBand++;
        }
        if (!nearEdge.empty() && nearEdge.at<uint8_t>(py, px))
        {
            score.nearEdge++;
            continue;
        }
        score.add(truth, said);
        if (!truth && said)
        {
            if (distance.empty())
                cv::distanceTransform(mask == 0, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
            countFalsePositive(score, distance, px, py, columns.of(cells));
        }
    }
    return score;
}
}  // namespace smap::eval
