// Reading one image file of a recording so that a damaged file is a reason, never a crash: the
// file is checked (missing, empty), the size in a PNG or JPEG header is checked against the size
// expected before anything is decoded (a corrupt header must not make the decoder allocate a
// huge image), then it is decoded.
#pragma once

#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>

namespace smap::io
{
struct ImageFileRead
{
    cv::Mat image;           ///< empty when `problem` is set
    std::string problem;     ///< why the file is unusable ("missing", "empty (0 bytes)", ...)
    bool wrongSize = false;  ///< the problem is a size other than the one expected
};

/// Reads `path` with cv::imdecode `flags`. `expected`, when not empty, is the size the image
/// must have: a header (or a decoded image) of another size is a problem.
ImageFileRead readImageFile(const std::string& path, int flags, const cv::Size& expected = {});

/// Width and height from the header of a PNG or baseline/progressive JPEG in `bytes`;
/// std::nullopt for other formats or a header too short to tell.
std::optional<cv::Size> imageSizeFromHeader(const std::string& bytes);
}  // namespace smap::io
