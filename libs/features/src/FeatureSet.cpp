#include "smap/features/FeatureSet.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace smap::features
{
ScalePyramid ScalePyramid::make(int levels, double factor)
{
    ScalePyramid p;
    p.scaleFactor = static_cast<float>(factor);
    p.logScaleFactor = static_cast<float>(std::log(factor));
    double s = 1.0;
    for (int l = 0; l < levels; ++l)
    {
        p.scale.push_back(static_cast<float>(s));
        p.invSigma2.push_back(static_cast<float>(1.0 / (s * s)));
        s *= factor;
    }
    return p;
}

void undistortKeypoints(FeatureSet& features, const core::PinholeCamera& camera)
{
    features.undistorted.resize(features.keypoints.size());
    for (size_t i = 0; i < features.keypoints.size(); ++i)
        features.undistorted[i] = features.keypoints[i].pt;
    if (!camera.hasDistortion() || features.keypoints.empty())
        return;
    const cv::Mat K = camera.cameraMatrix();
    cv::undistortPoints(features.undistorted, features.undistorted, K, camera.distCoeffs(),
                        cv::noArray(), K);
}

void assignDepth(FeatureSet& features, const cv::Mat& depth, double bf, double min_depth,
                 double max_depth, double edge_ratio)
{
    const size_t n = features.keypoints.size();
    features.depth.assign(n, 0.0F);
    features.rightU.assign(n, -1.0F);
    if (depth.empty())
        return;
    for (size_t i = 0; i < n; ++i)
    {
        const cv::Point2f& p = features.keypoints[i].pt;
        const int u = static_cast<int>(std::lround(p.x));
        const int v = static_cast<int>(std::lround(p.y));
        if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows)
            continue;
        const float z = depth.at<float>(v, u);
        if (!(z > 0.0F && z >= min_depth && z <= max_depth))
            continue;
        constexpr int kR = 2;
        float lo = z, hi = z;
        for (int y = std::max(0, v - kR); y <= std::min(depth.rows - 1, v + kR); ++y)
        {
            const auto* row = depth.ptr<float>(y);
            for (int x = std::max(0, u - kR); x <= std::min(depth.cols - 1, u + kR); ++x)
            {
                if (row[x] <= 0.0F)
                    continue;
                lo = std::min(lo, row[x]);
                hi = std::max(hi, row[x]);
            }
        }
        if (hi - lo <= edge_ratio * z)
        {
            features.depth[i] = z;
            features.rightU[i] = features.undistorted[i].x - static_cast<float>(bf / z);
        }
    }
}
}  // namespace smap::features
