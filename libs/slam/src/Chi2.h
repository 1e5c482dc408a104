// Chi-square bounds of a keypoint's information-weighted reprojection error, shared by the
// matchers' gates and the optimisers' outlier tests.
#pragma once

namespace smap::slam
{
/// 95 % quantile with 2 degrees of freedom: pixel (u, v) only.
constexpr double kChi2Mono = 5.991;
/// 95 % quantile with 3 degrees of freedom: pixel and the virtual right column uR.
constexpr double kChi2Stereo = 7.815;
}  // namespace smap::slam
