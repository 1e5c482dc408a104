// What the dynamic filter decided for one frame, for people to look at: a picture in the style
// of the paper's Figure 4 (static keypoints as red dots, dynamic ones as green crosses) and a
// CSV table with one row of evidence per keypoint.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>

#include "smap/dynamic/DynamicFilter.h"
#include "smap/features/FeatureSet.h"

namespace smap::dynamic
{
/// BGR copy of `colour` (BGR or grey) with every keypoint drawn: red dot = static, green "+" =
/// dynamic, grey dot = not evaluated (first frame); a caption gives the counts and tau.
cv::Mat drawEvidence(const cv::Mat& colour, const features::FeatureSet& features,
                     const DynamicResult& result);

/// "u,v,depth_m,residual_px,patch_error,flow,depth_test,region,isolated,was_dynamic,semantic,
/// dynamic" then one row per
/// keypoint (distorted pixel position; residual -1 where there was no flow measurement). A frame
/// the filter did not evaluate starts with the comment line "# not evaluated ...".
std::string evidenceCsv(const features::FeatureSet& features, const DynamicResult& result);
}  // namespace smap::dynamic
