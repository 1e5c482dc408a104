#include "smap/dynamic/FrameWarp.h"

#include <cmath>
#include <vector>

namespace smap::dynamic
{
namespace
{
/// Pinholes (a surface seen from closer covers more pixels): mean of the 3x3 neighbours that
/// were valid before the pass, where at least 3 are, `fill_passes` times.
void fillPinholes(WarpedFrame& out, int fill_passes)
{
    const int w = out.grey.cols, h = out.grey.rows;
    cv::Mat filled = out.valid.clone();
    for (int pass = 0; pass < fill_passes; ++pass)
    {
        const cv::Mat before = filled.clone();
        for (int v = 1; v < h - 1; ++v)
        {
            const uint8_t* b[3] = {before.ptr<uint8_t>(v - 1), before.ptr<uint8_t>(v),
                                   before.ptr<uint8_t>(v + 1)};
            const uint8_t* g[3] = {out.grey.ptr<uint8_t>(v - 1), out.grey.ptr<uint8_t>(v),
                                   out.grey.ptr<uint8_t>(v + 1)};
            const float* z[3] = {out.depth.ptr<float>(v - 1), out.depth.ptr<float>(v),
                                 out.depth.ptr<float>(v + 1)};
            uint8_t* grow = out.grey.ptr<uint8_t>(v);
            float* zrow = out.depth.ptr<float>(v);
            uint8_t* frow = filled.ptr<uint8_t>(v);
            for (int u = 1; u < w - 1; ++u)
            {
                if (b[1][u] != 0)
                    continue;
                int sum = 0, n = 0;
                float zsum = 0.0F;
                for (int r = 0; r < 3; ++r)
                {
                    for (int du = -1; du <= 1; ++du)
                    {
                        if (b[r][u + du] == 0)
                            continue;
                        sum += g[r][u + du];
                        zsum += z[r][u + du];
                        n++;
                    }
                }
                if (n >= 3)
                {
                    grow[u] = static_cast<uint8_t>(sum / n);
                    zrow[u] = zsum / static_cast<float>(n);
                    frow[u] = 255;
                }
            }
        }
    }
}
}  // namespace

WarpedFrame warpIntoCurrentView(const cv::Mat& previous_grey, const cv::Mat& previous_depth,
                                const core::PinholeCamera& camera,
                                const Eigen::Isometry3d& T_cur_prev, int fill_passes)
{
    CV_Assert(previous_grey.type() == CV_8UC1 && previous_depth.type() == CV_32FC1);
    CV_Assert(previous_grey.size() == previous_depth.size());
    const int w = previous_grey.cols, h = previous_grey.rows;
    WarpedFrame out;
    out.grey = cv::Mat::zeros(h, w, CV_8UC1);
    out.depth = cv::Mat::zeros(h, w, CV_32FC1);
    out.valid = cv::Mat::zeros(h, w, CV_8UC1);
    const Eigen::Matrix3f R = T_cur_prev.linear().cast<float>();
    const Eigen::Vector3f t = T_cur_prev.translation().cast<float>();
    const auto fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
    const auto cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
    // R * ray(u, v) = R.col(0) * x(u) + (R.col(1) * y(v) + R.col(2)): column and row parts.
    std::vector<Eigen::Vector3f> columnPart(static_cast<size_t>(w));
    for (int u = 0; u < w; ++u)
        columnPart[static_cast<size_t>(u)] = R.col(0) * ((static_cast<float>(u) - cx) / fx);
    for (int v = 0; v < h; ++v)
    {
        const auto* zrow = previous_depth.ptr<float>(v);
        const auto* grow = previous_grey.ptr<uint8_t>(v);
        const Eigen::Vector3f rowPart = R.col(1) * ((static_cast<float>(v) - cy) / fy) + R.col(2);
        for (int u = 0; u < w; ++u)
        {
            const float z = zrow[u];
            if (z <= 0.0F)
                continue;
            const Eigen::Vector3f p = z * (rowPart + columnPart[static_cast<size_t>(u)]) + t;
            if (p.z() <= 1e-3F)
                continue;
            const float iz = 1.0F / p.z();
            const int u2 = static_cast<int>(std::lround(fx * p.x() * iz + cx));
            const int v2 = static_cast<int>(std::lround(fy * p.y() * iz + cy));
            if (u2 < 0 || v2 < 0 || u2 >= w || v2 >= h)
                continue;
            float& zd = out.depth.at<float>(v2, u2);
            if (zd == 0.0F || p.z() < zd)
            {
                zd = p.z();
                out.grey.at<uint8_t>(v2, u2) = grow[u];
                out.valid.at<uint8_t>(v2, u2) = 255;
            }
        }
    }
    fillPinholes(out, fill_passes);
    return out;
}
}  // namespace smap::dynamic
