// Dynamic-keypoint detection scored against ground-truth dynamic masks: a keypoint is truly
// dynamic when the mask is non-zero at its (rounded) pixel.
#pragma once

#include <string>

#include "smap/core/JsonWriter.h"

namespace smap::eval
{
struct KeypointDetectionScore
{
    size_t truePositives = 0, falsePositives = 0, falseNegatives = 0, trueNegatives = 0;
    size_t frames = 0;

    void add(bool truth, bool said);
    KeypointDetectionScore& operator+=(const KeypointDetectionScore& o);
    double recall() const;     ///< 1 when there is nothing to find
    double precision() const;  ///< 1 when nothing was said
    core::JsonValue toJson() const;
};

/// Scores one frame: `evidence_csv` is the filter's per-keypoint table (semantic-mapper
/// --dynamic-debug: columns u, v first, dynamic last), `mask_png` the ground-truth mask (8-bit,
/// same size as the image). A table marked "# not evaluated" scores nothing (frames = 0).
/// Throws core::InputError naming the file on unreadable or malformed input.
KeypointDetectionScore scoreKeypointFrame(const std::string& evidence_csv,
                                          const std::string& mask_png);
}  // namespace smap::eval
