// Range images that MRPT stores outside the rawlog (CObservation3DRangeScan external storage):
// "*.bin" = gzip-compressed MRPT archive of uint32 rows, uint32 cols, rows*cols uint16 (row
// major, little endian), as MRPT 2.x writes them; "*.txt" = whitespace-separated matrix.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>

namespace smap::io
{
/// Returns a CV_16UC1 image. Throws core::InputError naming the file when it is missing or
/// malformed.
cv::Mat readExternalRangeImage(const std::string& path);
}  // namespace smap::io
