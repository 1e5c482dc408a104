#include "smap/core/RgbdFrame.h"

#include <mrpt/core/format.h>

#include <opencv2/core.hpp>
#include <stdexcept>

namespace smap::core
{
void RgbdFrame::validate() const
{
    if (colour.type() != CV_8UC3)
        throw std::logic_error(mrpt::format("frame %zu: colour is not CV_8UC3", index));
    if (depth.type() != CV_32FC1)
        throw std::logic_error(mrpt::format("frame %zu: depth is not CV_32FC1", index));
    if (colour.size() != depth.size())
    {
        throw std::logic_error(mrpt::format("frame %zu: colour %dx%d and depth %dx%d differ", index,
                                            colour.cols, colour.rows, depth.cols, depth.rows));
    }
    if (camera.width != colour.cols || camera.height != colour.rows)
    {
        throw std::logic_error(mrpt::format("frame %zu: camera %dx%d does not match image %dx%d",
                                            index, camera.width, camera.height, colour.cols,
                                            colour.rows));
    }
}

double RgbdFrame::validDepthFraction() const
{
    if (depth.empty())
        return 0.0;
    return static_cast<double>(cv::countNonZero(depth > 0.0f)) / static_cast<double>(depth.total());
}
}  // namespace smap::core
