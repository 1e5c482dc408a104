#include "smap/eval/TrajectoryPlot.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "smap/core/AtomicFile.h"

namespace smap::eval
{
namespace
{
const cv::Scalar kBlack(0, 0, 0), kGrey(215, 215, 215), kDarkGrey(90, 90, 90);
const cv::Scalar kGroundTruth(30, 30, 30), kEstimate(200, 110, 20), kError(60, 60, 230);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

/// 1, 2 or 5 times a power of ten, so that about `targetTicks` ticks span `range`.
double niceStep(double range, int targetTicks)
{
    const double raw = range / std::max(1, targetTicks);
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
    {
        if (m * p >= raw)
            return m * p;
    }
    return 10.0 * p;
}

std::array<int, 2> chooseAxes(const AteResult& ate, const PlotOptions& o)
{
    if (o.horizontalAxis >= 0 && o.verticalAxis >= 0)
        return {o.horizontalAxis, o.verticalAxis};
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), var = Eigen::Vector3d::Zero();
    for (const auto& p : ate.perPose)
        mean += p.gtPosition;
    mean /= std::max<size_t>(1, ate.perPose.size());
    for (const auto& p : ate.perPose)
        var += (p.gtPosition - mean).cwiseAbs2();
    int drop = 0;
    var.minCoeff(&drop);
    std::array<int, 2> axes{};
    int k = 0;
    for (int a = 0; a < 3; a++)
    {
        if (a != drop)
            axes[static_cast<size_t>(k++)] = a;
    }
    return axes;
}

void putText(cv::Mat& img, const std::string& s, cv::Point org, double scale, const cv::Scalar& c,
             int thick = 1)
{
    cv::putText(img, s, org, kFont, scale, c, thick, cv::LINE_AA);
}

std::string tickLabel(double v, double step)
{
    const int decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step))));
    return mrpt::format("%.*f", decimals, std::abs(v) < 1e-12 ? 0.0 : v);
}
/// World-to-pixel mapping of the plot area: equal scale on both axes, the data centred with a
/// 5% margin.
struct PlotFrame
{
    cv::Rect area;
    std::array<int, 2> axes{};
    double scale = 1.0, cx = 0.0, cy = 0.0;

    cv::Point2d toPixel(const Eigen::Vector3d& v) const
    {
        return {area.x + area.width / 2.0 + (v[axes[0]] - cx) * scale,
                area.y + area.height / 2.0 - (v[axes[1]] - cy) * scale};
    }
};

PlotFrame fitPlotFrame(const AteResult& ate, const std::array<int, 2>& axes, const cv::Rect& area)
{
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const auto& p : ate.perPose)
    {
        for (int k = 0; k < 2; k++)
        {
            for (const auto* v : {&p.gtPosition, &p.estPositionAligned})
            {
                lo[k] = std::min(lo[k], (*v)[axes[static_cast<size_t>(k)]]);
                hi[k] = std::max(hi[k], (*v)[axes[static_cast<size_t>(k)]]);
            }
        }
    }
    if (ate.perPose.empty())
        lo[0] = lo[1] = -1, hi[0] = hi[1] = 1;
    const double span = std::max({hi[0] - lo[0], (hi[1] - lo[1]) * area.width / area.height, 1e-3});
    PlotFrame f;
    f.area = area;
    f.axes = axes;
    f.scale = area.width / (1.1 * span);
    f.cx = 0.5 * (lo[0] + hi[0]);
    f.cy = 0.5 * (lo[1] + hi[1]);
    return f;
}

void drawGrid(cv::Mat& img, const PlotFrame& f)
{
    const cv::Rect& area = f.area;
    const double step = niceStep(area.width / f.scale, 8);
    const double x0 = f.cx - area.width / (2 * f.scale), x1 = f.cx + area.width / (2 * f.scale);
    const double y0 = f.cy - area.height / (2 * f.scale), y1 = f.cy + area.height / (2 * f.scale);
    for (double x = std::ceil(x0 / step) * step; x <= x1; x += step)
    {
        const int px =
            static_cast<int>(std::lround(area.x + area.width / 2.0 + (x - f.cx) * f.scale));
        cv::line(img, {px, area.y}, {px, area.y + area.height}, kGrey, 1);
        putText(img, tickLabel(x, step), {px - 18, area.y + area.height + 22}, 0.5, kDarkGrey);
    }
    for (double y = std::ceil(y0 / step) * step; y <= y1; y += step)
    {
        const int py =
            static_cast<int>(std::lround(area.y + area.height / 2.0 - (y - f.cy) * f.scale));
        cv::line(img, {area.x, py}, {area.x + area.width, py}, kGrey, 1);
        putText(img, tickLabel(y, step), {8, py + 5}, 0.5, kDarkGrey);
    }
    cv::rectangle(img, area, kBlack, 1);
}

void drawTrajectories(cv::Mat& img, const AteResult& ate, const PlotFrame& f)
{
    const int shift = 4;  // sub-pixel drawing
    auto fixed = [&](const Eigen::Vector3d& v)
    {
        const cv::Point2d p = f.toPixel(v);
        return cv::Point(static_cast<int>(std::lround(p.x * (1 << shift))),
                         static_cast<int>(std::lround(p.y * (1 << shift))));
    };
    for (const auto& p : ate.perPose)
        cv::line(img, fixed(p.gtPosition), fixed(p.estPositionAligned), kError, 1, cv::LINE_AA,
                 shift);
    // Estimate first, ground truth on top, so the reference stays visible.
    for (size_t i = 1; i < ate.perPose.size(); i++)
        cv::line(img, fixed(ate.perPose[i - 1].estPositionAligned),
                 fixed(ate.perPose[i].estPositionAligned), kEstimate, 2, cv::LINE_AA, shift);
    for (size_t i = 1; i < ate.perPose.size(); i++)
        cv::line(img, fixed(ate.perPose[i - 1].gtPosition), fixed(ate.perPose[i].gtPosition),
                 kGroundTruth, 2, cv::LINE_AA, shift);
}

/// Legend, top right inside the plot area.
void drawLegend(cv::Mat& img, const cv::Rect& area)
{
    const cv::Rect legend(area.x + area.width - 210, area.y + 10, 200, 80);
    cv::rectangle(img, legend, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(img, legend, kDarkGrey, 1);
    const std::array<std::pair<const char*, cv::Scalar>, 3> entries = {
        {{"ground truth", kGroundTruth},
         {"estimate (aligned)", kEstimate},
         {"difference", kError}}};
    for (size_t i = 0; i < entries.size(); i++)
    {
        const int y = legend.y + 20 + static_cast<int>(i) * 22;
        cv::line(img, {legend.x + 10, y - 5}, {legend.x + 45, y - 5}, entries[i].second, 2,
                 cv::LINE_AA);
        putText(img, entries[i].first, {legend.x + 55, y}, 0.5, kBlack);
    }
}
}  // namespace

cv::Mat renderAtePlot(const AteResult& ate, const PlotOptions& o)
{
    cv::Mat img(o.height, o.width, CV_8UC3, cv::Scalar(255, 255, 255));
    const auto axes = chooseAxes(ate, o);
    const char* names[3] = {"x", "y", "z"};
    const int left = 90, right = 30, top = 70, bottom = 70;
    const cv::Rect area(left, top, o.width - left - right, o.height - top - bottom);
    const PlotFrame frame = fitPlotFrame(ate, axes, area);
    drawGrid(img, frame);
    drawTrajectories(img, ate, frame);
    putText(img, o.title, {left, 30}, 0.75, kBlack, 2);
    putText(img,
            mrpt::format("RMSE %.4f m   mean %.4f m   max %.4f m   %zu pairs", ate.translation.rmse,
                         ate.translation.mean, ate.translation.max, ate.pairs),
            {left, 55}, 0.55, kDarkGrey);
    putText(img, mrpt::format("%s [m]", names[axes[0]]),
            {area.x + area.width / 2 - 15, o.height - 18}, 0.6, kBlack);
    putText(img, mrpt::format("%s [m]", names[axes[1]]), {8, area.y - 10}, 0.6, kBlack);
    drawLegend(img, area);
    return img;
}

void saveAtePlot(const std::string& path, const AteResult& ate, const PlotOptions& options)
{
    const cv::Mat img = renderAtePlot(ate, options);
    core::writeFileAtomically(
        path,
        [&](const std::string& tmp)
        {
            if (!cv::imwrite(tmp, img))
                throw std::runtime_error(mrpt::format("cannot write plot '%s'", path.c_str()));
        });
}
}  // namespace smap::eval
