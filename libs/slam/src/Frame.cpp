#include "smap/slam/Frame.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "smap/slam/MapPoint.h"

namespace smap::slam
{
namespace
{
/// Per-keypoint outside input must have one value per keypoint.
void requireOnePerKeypoint(const char* what, size_t n, size_t keypoints)
{
    if (n != keypoints)
        throw std::invalid_argument(std::string(what) + ": " + std::to_string(n) + " values for " +
                                    std::to_string(keypoints) + " keypoints");
}
}  // namespace

void Frame::setWeights(const std::vector<float>& w)
{
    if (w.empty())
    {
        weights.assign(size(), 1.0F);
        return;
    }
    requireOnePerKeypoint("feature weights", w.size(), size());
    for (float x : w)
        if (!(x >= 0.0F && x <= 1.0F))
            throw std::invalid_argument("feature weight " + std::to_string(x) + " outside [0, 1]");
    weights = w;
}

void Frame::setMappable(const std::vector<bool>& m)
{
    if (!m.empty())
        requireOnePerKeypoint("mappable flags", m.size(), size());
    mappable = m;
}

void Frame::setMask(const cv::Mat& mask)
{
    if (mask.empty())
    {
        weights.assign(size(), 1.0F);
        return;
    }
    if (mask.type() != CV_8UC1)
        throw std::invalid_argument("feature mask must be CV_8UC1");
    weights.assign(size(), 1.0F);
    for (size_t i = 0; i < size(); ++i)
    {
        const cv::Point2f& p = features.keypoints[i].pt;
        const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
        if (u >= 0 && v >= 0 && u < mask.cols && v < mask.rows && mask.at<uint8_t>(v, u) == 0)
            weights[i] = 0.0F;
    }
}

std::vector<size_t> Frame::usableKeypoints() const
{
    std::vector<size_t> out;
    for (size_t i = 0; i < size(); ++i)
        if (usable(i))
            out.push_back(i);
    return out;
}

void Frame::clearMatches()
{
    points.assign(size(), nullptr);
    outlier.assign(size(), false);
}

int Frame::discardOutliers()
{
    int inMap = 0;
    for (size_t i = 0; i < size(); ++i)
    {
        if (!points[i])
            continue;
        if (outlier[i])
        {
            points[i].reset();
            outlier[i] = false;
        }
        else if (points[i]->numObservations() > 0)
        {
            inMap++;
        }
    }
    return inMap;
}

int Frame::countMatches() const
{
    int n = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (points[i] && !outlier[i])
            n++;
    return n;
}

cv::Mat makeThumbnail(const cv::Mat& image)
{
    cv::Mat grey, small, f;
    if (image.channels() == 3)
        cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    else
        grey = image;
    cv::resize(grey, small, cv::Size(40, 30), 0, 0, cv::INTER_AREA);
    small.convertTo(f, CV_32F);
    cv::GaussianBlur(f, f, cv::Size(5, 5), 1.5);
    f -= cv::mean(f)[0];
    const double n = cv::norm(f);
    if (n > 1e-6)
        f /= n;
    return f;
}

double thumbnailSimilarity(const cv::Mat& a, const cv::Mat& b)
{
    if (a.empty() || b.empty())
        return -1.0;
    return a.dot(b);
}
}  // namespace smap::slam
