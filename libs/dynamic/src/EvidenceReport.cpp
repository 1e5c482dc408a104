#include "smap/dynamic/EvidenceReport.h"

#include <mrpt/core/format.h>

#include <opencv2/imgproc.hpp>
#include <sstream>

namespace smap::dynamic
{
cv::Mat drawEvidence(const cv::Mat& colour, const features::FeatureSet& features,
                     const DynamicResult& result)
{
    cv::Mat out;
    if (colour.channels() == 1)
        cv::cvtColor(colour, out, cv::COLOR_GRAY2BGR);
    else
        out = colour.clone();
    const cv::Scalar red(0, 0, 255), green(0, 255, 0), grey(160, 160, 160);
    for (size_t i = 0; i < features.size() && i < result.keypoints.size(); ++i)
    {
        const cv::Point p(cvRound(features.keypoints[i].pt.x), cvRound(features.keypoints[i].pt.y));
        if (!result.evaluated)
            cv::circle(out, p, 2, grey, cv::FILLED, cv::LINE_AA);
        else if (result.keypoints[i].dynamic)
            cv::drawMarker(out, p, green, cv::MARKER_CROSS, 9, 2);
        else
            cv::circle(out, p, 2, red, cv::FILLED, cv::LINE_AA);
    }
    const std::string caption =
        result.evaluated ? mrpt::format("%zu dynamic (green +) / %zu keypoints, tau %.1f px",
                                        result.numDynamic(), features.size(), result.tau)
                         : std::string("first frame: not evaluated");
    cv::putText(out, caption, {6, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 3,
                cv::LINE_AA);
    cv::putText(out, caption, {6, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1,
                cv::LINE_AA);
    return out;
}

std::string evidenceCsv(const features::FeatureSet& features, const DynamicResult& result)
{
    std::ostringstream s;
    if (!result.evaluated)
        s << "# not evaluated (no previous frame): no decision was made\n";
    s << "u,v,depth_m,residual_px,patch_error,flow,depth_test,region,isolated,was_dynamic,"
         "semantic,dynamic\n";
    for (size_t i = 0; i < features.size() && i < result.keypoints.size(); ++i)
    {
        const auto& e = result.keypoints[i];
        const float z = features.depth.empty() ? 0.0F : features.depth[i];
        s << mrpt::format("%.2f,%.2f,%.4f,%.3f,%.2f,%d,%d,%d,%d,%d,%d,%d\n",
                          features.keypoints[i].pt.x, features.keypoints[i].pt.y, z, e.residual,
                          e.patchError, e.flow ? 1 : 0, e.depth ? 1 : 0, e.region ? 1 : 0,
                          e.isolated ? 1 : 0, e.wasDynamic ? 1 : 0, e.semantic ? 1 : 0,
                          e.dynamic ? 1 : 0);
    }
    return s.str();
}
}  // namespace smap::dynamic
