#include "smap/eval/KeypointDetectionScore.h"

#include <mrpt/core/format.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
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
    return *this;
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
    return j;
}

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
    // Pixels whose square neighbourhood holds both labels: the dilated and eroded masks differ.
    cv::Mat nearEdge;
    if (edge_margin > 0)
    {
        const cv::Mat binary = mask != 0;
        const cv::Mat box = cv::getStructuringElement(
            cv::MORPH_RECT, cv::Size(2 * edge_margin + 1, 2 * edge_margin + 1));
        cv::Mat grown, shrunk;
        cv::dilate(binary, grown, box, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
        cv::erode(binary, shrunk, box, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
        nearEdge = grown != shrunk;
    }
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
        if (!nearEdge.empty() && nearEdge.at<uint8_t>(static_cast<int>(y), static_cast<int>(x)))
        {
            score.nearEdge++;
            continue;
        }
        score.add(mask.at<uint8_t>(static_cast<int>(y), static_cast<int>(x)) != 0,
                  cells.back() == "1");
    }
    return score;
}
}  // namespace smap::eval
