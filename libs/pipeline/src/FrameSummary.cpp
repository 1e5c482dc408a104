#include "smap/pipeline/FrameSummary.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <opencv2/core.hpp>
#include <vector>

namespace smap::pipeline
{
FrameStats computeFrameStats(const core::RgbdFrame& frame)
{
    FrameStats s;
    s.index = frame.index;
    s.timestamp = frame.timestamp;
    s.name = frame.name;
    std::vector<float> valid;
    valid.reserve(frame.depth.total());
    for (int r = 0; r < frame.depth.rows; r++)
    {
        const float* row = frame.depth.ptr<float>(r);
        for (int c = 0; c < frame.depth.cols; c++)
        {
            if (row[c] > 0.0f)
                valid.push_back(row[c]);
        }
    }
    if (!frame.depth.empty())
        s.validDepthFraction =
            static_cast<double>(valid.size()) / static_cast<double>(frame.depth.total());
    if (!valid.empty())
    {
        const auto [lo, hi] = std::minmax_element(valid.begin(), valid.end());
        s.depthMin = *lo;
        s.depthMax = *hi;
        auto mid = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2);
        std::nth_element(valid.begin(), mid, valid.end());
        s.depthMedian = *mid;
    }
    if (!frame.colour.empty())
    {
        const cv::Scalar m = cv::mean(frame.colour);
        // Rec. 601 luma of the BGR means.
        s.meanIntensity = 0.114 * m[0] + 0.587 * m[1] + 0.299 * m[2];
    }
    return s;
}

std::string frameStatsCsvHeader()
{
    return "index,timestamp,name,valid_depth_fraction,depth_min_m,depth_median_m,depth_max_m,mean_"
           "intensity";
}

std::string toCsvRow(const FrameStats& s)
{
    return mrpt::format("%zu,%.6f,%s,%.4f,%.4f,%.4f,%.4f,%.2f", s.index, s.timestamp,
                        s.name.c_str(), s.validDepthFraction, s.depthMin, s.depthMedian, s.depthMax,
                        s.meanIntensity);
}
}  // namespace smap::pipeline
