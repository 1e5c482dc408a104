// Dynamic-keypoint detection scored against ground-truth dynamic masks: a keypoint is truly
// dynamic when the mask is non-zero at its (rounded) pixel. Optionally, keypoints within a few
// pixels of a mask edge are left out: a corner on a person's outline is as likely to sit one
// pixel outside the mask as inside, though it moves with the person either way.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "smap/core/JsonWriter.h"

namespace smap::eval
{
struct KeypointDetectionScore
{
    size_t truePositives = 0, falsePositives = 0, falseNegatives = 0, trueNegatives = 0;
    size_t frames = 0;
    size_t nearEdge = 0;  ///< keypoints left out as within the edge margin of a mask edge

    /// Where the false positives are: by distance (px) from the nearest mask pixel, up to
    /// kDistanceBands[k] in band k, beyond the last in the last band.
    static constexpr std::array<double, 4> kDistanceBands{1.5, 3.0, 10.0, 50.0};
    std::array<size_t, kDistanceBands.size() + 1> falsePositivesByDistance{};
    /// By the evidence that decided them, first that applies: the flow test, the depth test,
    /// region growing, semantic evidence alone, anything else (a table without those columns).
    enum class Evidence : uint8_t
    {
        Flow,
        Depth,
        Region,
        SemanticOnly,
        Other,
        Count
    };
    std::array<size_t, static_cast<size_t>(Evidence::Count)> falsePositivesByEvidence{};

    /// The outline band: keypoints within kOutlineBandPx of a mask edge (the square around
    /// their pixel holds both mask and non-mask pixels), scored or not. If the decisions
    /// there are flagged at the same rate on the person's side as beside it, nothing in them
    /// tells the sides apart and the band's label is a coin flip for the score.
    static constexpr int kOutlineBandPx = 3;
    /// The recall the outline bound is reported at: the project's target (docs/dynamic.md).
    static constexpr double kTargetRecall = 0.95;
    struct BandSide
    {
        size_t keypoints = 0, said = 0;
        double saidFraction() const;  ///< 0 when there are none
    };
    BandSide bandOnMask, bandBesideMask;
    /// Keypoints on a mask outside the outline band, scored or not.
    size_t maskOffBand = 0;

    void add(bool truth, bool said);
    KeypointDetectionScore& operator+=(const KeypointDetectionScore& o);
    double recall() const;     ///< 1 when there is nothing to find
    double precision() const;  ///< 1 when nothing was said
    /// The precision if every false positive farther than `px` from a mask (one of
    /// kDistanceBands) were not said: what deciding the outline corners by motion, which move
    /// with the person, leaves at best.
    double precisionWithin(double px) const;
    /// The best precision at `recall` (0..1) of a decision that is right on every keypoint off
    /// the outline band and says dynamic at one rate on both sides of it, the least rate that
    /// reaches `recall`: what deciding the outline by motion allows at best, the corners there
    /// moving with the person on either side. 1 when the keypoints off the band reach `recall`
    /// alone.
    double bestPrecisionAtRecall(double recall) const;
    core::JsonValue toJson() const;
};

/// Whose decisions a keypoint score takes.
enum class KeypointDecision : uint8_t
{
    Table,         ///< the evidence table's `dynamic` column
    Labels,        ///< a label image (a segmentation): dynamic where it holds a said label
    LabelsInBand,  ///< the label image within the outline band, the table everywhere else
};

struct KeypointScoreOptions
{
    /// > 0 leaves out (counts in nearEdge) the keypoints whose (2 edgeMargin + 1) square around
    /// their pixel holds both mask and non-mask pixels; 0 scores every keypoint.
    int edgeMargin = 0;
    KeypointDecision decision = KeypointDecision::Table;
    /// For Labels and LabelsInBand: 8-bit class ids of the mask's size (smap-segment's output),
    /// and the ids said dynamic there.
    std::string labelPng;
    std::vector<int> saidLabels;
};

/// Scores one frame: `evidence_csv` is the filter's per-keypoint table (semantic-mapper
/// --dynamic-debug: columns u, v first, dynamic last), `mask_png` the ground-truth mask (8-bit,
/// same size as the image). A table marked "# not evaluated" scores nothing (frames = 0).
/// The outline band (kOutlineBandPx) is counted whatever the margin.
/// False positives are broken down by distance and by the table's evidence columns (flow,
/// depth_test, region, semantic) where it has them; a label image's decisions count as other.
/// Throws core::InputError naming the file on unreadable or malformed input.
KeypointDetectionScore scoreKeypointFrame(const std::string& evidence_csv,
                                          const std::string& mask_png,
                                          const KeypointScoreOptions& options);
}  // namespace smap::eval
