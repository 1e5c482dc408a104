// One RGB-D frame as every stage of semantic-mapper sees it, whatever the source.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>

#include "smap/core/PinholeCamera.h"

namespace smap::core
{
/// Colour and depth on the same pixel grid, described by `camera`.
///
/// - colour: CV_8UC3 in OpenCV's BGR channel order.
/// - depth: CV_32FC1, metres along the optical axis (+Z, not the ray length), registered to
///   the colour image. Invalid depth (no return, out of range, holes) is exactly 0.0f; there
///   are no NaNs and no negative values.
/// - camera: intrinsics of the colour image (distortion included where the source has one).
struct RgbdFrame
{
    cv::Mat colour;
    cv::Mat depth;
    PinholeCamera camera;
    double timestamp = 0.0;  ///< seconds (UNIX time for MRPT sources, file time for TUM)
    size_t index = 0;        ///< 0-based position in the source
    std::string name;        ///< source-specific id, e.g. the colour file stem

    /// Checks types and sizes against each other and the camera; throws std::logic_error.
    void validate() const;
    /// Fraction of pixels with valid (> 0) depth.
    double validDepthFraction() const;
};
}  // namespace smap::core
