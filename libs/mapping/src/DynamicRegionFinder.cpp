#include "smap/mapping/DynamicRegionFinder.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "smap/core/InputError.h"
#include "smap/core/OptionFields.h"

namespace smap::mapping
{
namespace
{
/// Grows `mask` (CV_8UC1, 255 = in) by up to `steps` 4-neighbour rings into pixels with depth
/// within `tolerance` of the mask pixel they touch; returns how many joined. Only pixels that
/// joined in the previous step can reach new ones (a pixel an older one could have taken was
/// already refused), so the cost is the mask's size plus what grows.
int growAlongDepth(cv::Mat& mask, const cv::Mat& depth, int steps, float tolerance)
{
    // Indexing by i = v * cols + u needs one block (a view into a larger image is copied).
    const cv::Mat depthBlock = depth.isContinuous() ? depth : depth.clone();
    const auto* z = depthBlock.ptr<float>();
    auto* m = mask.ptr<uint8_t>();
    const int cols = mask.cols, rows = mask.rows;
    std::vector<int> frontier, joined;
    for (int i = 0; i < cols * rows; ++i)
        if (m[i])
            frontier.push_back(i);
    int grown = 0;
    for (int step = 0; step < steps && !frontier.empty(); ++step)
    {
        joined.clear();
        for (const int i : frontier)
        {
            if (!(z[i] > 0.0f))
                continue;
            const auto tryJoin = [&](int j)
            {
                if (!m[j] && z[j] > 0.0f && std::abs(z[j] - z[i]) < tolerance)
                {
                    m[j] = 255;
                    joined.push_back(j);
                }
            };
            const int u = i % cols, v = i / cols;
            if (u > 0)
                tryJoin(i - 1);
            if (u + 1 < cols)
                tryJoin(i + 1);
            if (v > 0)
                tryJoin(i - cols);
            if (v + 1 < rows)
                tryJoin(i + cols);
        }
        grown += static_cast<int>(joined.size());
        frontier.swap(joined);
    }
    return grown;
}
}  // namespace

core::OptionFields DynamicRegionParameters::fields(const std::string& section)
{
    core::OptionFields f(section, "association");
    f.add("num_points", num_points)
        .add("depth_tolerance", depth_tolerance)
        .add("pixel_radius", pixel_radius)
        .add("non_object_classes", non_object_classes)
        .add("connectivity", connectivity)
        .add("grow_pixels", grow_pixels)
        .add("movable_prior", movable_prior);
    return f;
}

void DynamicRegionParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                                 const std::string& section)
{
    fields(section).load(cfg);
    if (num_points < 0)
        throw core::InputError(
            mrpt::format("[association] num_points = %d must be >= 0", num_points));
    if (!(depth_tolerance > 0.0) || !(pixel_radius > 0.0) || pixel_radius > 200.0)
        throw core::InputError(mrpt::format(
            "[association] depth_tolerance = %g must be > 0 and pixel_radius = %g in (0, 200]",
            depth_tolerance, pixel_radius));
    if (grow_pixels < 0 || grow_pixels > 100)
        throw core::InputError(
            mrpt::format("[association] grow_pixels = %d must be in [0, 100]", grow_pixels));
    if (!(movable_prior >= 0.0))
        throw core::InputError(mrpt::format(
            "[association] movable_prior = %g must be >= 0 (above 1: no class)", movable_prior));
    if (connectivity != 4 && connectivity != 8)
        throw core::InputError(
            mrpt::format("[association] connectivity = %d must be 4 or 8", connectivity));
}

void DynamicRegionParameters::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) const
{
    // Saving only reads the fields the list points at.
    const_cast<DynamicRegionParameters*>(this)->fields(section).save(cfg);
}

DynamicRegionFinder::DynamicRegionFinder(const DynamicRegionParameters& params,
                                         const core::LabelSet& labels)
    : params_(params)
{
    std::stringstream ss(params_.non_object_classes);
    for (std::string name; std::getline(ss, name, ',');)
    {
        name.erase(0, name.find_first_not_of(" \t"));
        name.erase(name.find_last_not_of(" \t") + 1);
        if (!name.empty())
            nonObject_.insert(labels.idOf(name));
    }
    const std::vector<bool> movable = labels.movable(params_.movable_prior);
    for (size_t id = 0; id < movable.size(); ++id)
        if (movable[id] && !nonObject_.count(static_cast<int>(id)))
            movable_.insert(static_cast<int>(id));
}

DynamicRegions DynamicRegionFinder::find(const cv::Mat& labels, const cv::Mat& depth,
                                         const std::vector<DynamicPoint>& points) const
{
    CV_Assert(labels.type() == CV_8UC1 && depth.type() == CV_32FC1 &&
              labels.size() == depth.size());
    DynamicRegions r;
    r.dynamicMask = cv::Mat::zeros(labels.size(), CV_8UC1);
    r.objectIds = cv::Mat(labels.size(), CV_32SC1, cv::Scalar(-1));
    findObjects(labels, r);
    markDynamicObjects(points, r);
    markAroundPoints(points, depth, r);
    // Beyond the paper: M grows into depth-continuous neighbours.
    if (params_.grow_pixels > 0)
        r.pixelsGrown = growAlongDepth(r.dynamicMask, depth, params_.grow_pixels,
                                       static_cast<float>(params_.depth_tolerance));
    return r;
}

namespace
{
/// The pixel of a point, when inside the image.
bool pixelOf(const DynamicPoint& p, const cv::Size& size, int& u, int& v)
{
    u = static_cast<int>(std::lround(p.u));
    v = static_cast<int>(std::lround(p.v));
    return u >= 0 && v >= 0 && u < size.width && v < size.height;
}
}  // namespace

void DynamicRegionFinder::findObjects(const cv::Mat& labels, DynamicRegions& r) const
{
    // Objects: connected regions of each class present (void and non-object classes aside).
    bool present[256] = {};
    for (int v = 0; v < labels.rows; v++)
    {
        const auto* l = labels.ptr<uint8_t>(v);
        for (int u = 0; u < labels.cols; u++)
            present[l[u]] = true;
    }
    cv::Mat components;
    for (int label = 0; label < core::LabelSet::kVoid; label++)
    {
        if (!present[label] || nonObject_.count(label))
            continue;
        const int n =
            cv::connectedComponents(labels == label, components, params_.connectivity, CV_32S);
        const int first = static_cast<int>(r.objects.size());
        for (int c = 1; c < n; c++)
            r.objects.push_back({label, 0, 0, false, movable_.count(label) > 0});
        for (int v = 0; v < labels.rows; v++)
        {
            const int* comp = components.ptr<int>(v);
            int* ids = r.objectIds.ptr<int>(v);
            for (int u = 0; u < labels.cols; u++)
                if (comp[u] > 0)
                {
                    ids[u] = first + comp[u] - 1;
                    r.objects[static_cast<size_t>(ids[u])].pixels++;
                }
        }
    }
}

void DynamicRegionFinder::markDynamicObjects(const std::vector<DynamicPoint>& points,
                                             DynamicRegions& r) const
{
    // Step 1: count the dynamic points on every object; more than Num -> the whole object.
    for (const auto& p : points)
    {
        int u = 0, v = 0;
        if (pixelOf(p, r.objectIds.size(), u, v) && r.objectIds.at<int>(v, u) >= 0)
            r.objects[static_cast<size_t>(r.objectIds.at<int>(v, u))].dynamicPoints++;
    }
    for (auto& o : r.objects)
        o.dynamic = o.dynamicPoints > params_.num_points || o.movable;
    for (int v = 0; v < r.objectIds.rows; v++)
    {
        const int* ids = r.objectIds.ptr<int>(v);
        auto* m = r.dynamicMask.ptr<uint8_t>(v);
        for (int u = 0; u < r.objectIds.cols; u++)
        {
            if (ids[u] < 0)
                continue;
            const ObjectRegion& o = r.objects[static_cast<size_t>(ids[u])];
            if (o.dynamic)
            {
                m[u] = 255;
                r.pixelsFromObjects++;
                r.pixelsMovable += o.dynamicPoints > params_.num_points ? 0 : 1;
            }
        }
    }
}

void DynamicRegionFinder::markAroundPoints(const std::vector<DynamicPoint>& points,
                                           const cv::Mat& depth, DynamicRegions& r) const
{
    // Step 2: around the remaining points, pixels near in the image and in depth.
    const double radius = params_.pixel_radius, radius2 = radius * radius;
    const cv::Size size = depth.size();
    for (const auto& p : points)
    {
        int pu = 0, pv = 0;
        const bool inside = pixelOf(p, size, pu, pv);
        if (inside)
        {
            const int id = r.objectIds.at<int>(pv, pu);
            if (id >= 0 && r.objects[static_cast<size_t>(id)].dynamic)
                continue;  // its object is gone already
        }
        double z = p.depth;
        if (!(z > 0.0) && inside)
            z = depth.at<float>(pv, pu);
        const int u0 = std::max(0, static_cast<int>(std::ceil(p.u - radius)));
        const int u1 = std::min(size.width - 1, static_cast<int>(std::floor(p.u + radius)));
        const int v0 = std::max(0, static_cast<int>(std::ceil(p.v - radius)));
        const int v1 = std::min(size.height - 1, static_cast<int>(std::floor(p.v + radius)));
        for (int v = v0; v <= v1; v++)
        {
            const float* d = depth.ptr<float>(v);
            auto* m = r.dynamicMask.ptr<uint8_t>(v);
            for (int u = u0; u <= u1; u++)
            {
                const double du = u - p.u, dv = v - p.v;
                if (m[u] || du * du + dv * dv >= radius2)
                    continue;
                // Without the point's depth only the image distance can decide; a pixel
                // without depth is never back-projected, so its decision is moot.
                if (z > 0.0 && !(d[u] > 0.0f && std::abs(d[u] - z) < params_.depth_tolerance))
                    continue;
                m[u] = 255;
                r.pixelsNearPoints++;
            }
        }
    }
}
}  // namespace smap::mapping
