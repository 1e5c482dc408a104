// Dynamic-keypoint detection scored against ground-truth dynamic masks: a keypoint is truly
// dynamic when the mask is non-zero at its (rounded) pixel. Optionally, keypoints within a few
// pixels of a mask edge are left out: a corner on a person's outline is as likely to sit one
// pixel outside the mask as inside, though it moves with the person either way.
#pragma once

#include <string>

#include "smap/core/JsonWriter.h"

namespace smap::eval
{
struct KeypointDetectionScore
{
    size_t truePositives = 0, falsePositives = 0, falseNegatives = 0, trueNegatives = 0;
    size_t frames = 0;
    size_t nearEdge = 0;  ///< keypoints left out as within the edge margin of a mask edge

    void add(bool truth, bool said);
    KeypointDetectionScore& operator+=(const KeypointDetectionScore& o);
    double recall() const;     ///< 1 when there is nothing to find
    double precision() const;  ///< 1 when nothing was said
    core::JsonValue toJson() const;
};

/// Scores one frame: `evidence_csv` is the filter's per-keypoint table (semantic-mapper
/// --dynamic-debug: columns u, v first, dynamic last), `mask_png` the ground-truth mask (8-bit,
/// same size as the image). A table marked "# not evaluated" scores nothing (frames = 0).
/// `edge_margin` > 0 leaves out (counts in nearEdge) the keypoints whose (2 edge_margin + 1)
/// square around their pixel holds both mask and non-mask pixels; 0 scores every keypoint.
/// Throws core::InputError naming the file on unreadable or malformed input.
KeypointDetectionScore scoreKeypointFrame(const std::string& evidence_csv,
                                          const std::string& mask_png, int edge_margin = 0);
}  // namespace smap::eval
