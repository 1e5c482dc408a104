#include "BodyVoxels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "KeyFrameVoxels.h"
#include "smap/core/LabelSet.h"
#include "smap/core/RecordingTime.h"

namespace smap::mapping
{
namespace
{
constexpr int kStep = 4;  ///< px between body samples

/// CV_8UC1: 255 where the class is movable, eroded by `erosion` px (beyond the image's border
/// counts as body: a person cut by it keeps that edge).
cv::Mat movableInside(const cv::Mat& labels, const std::vector<bool>& movable, int erosion)
{
    cv::Mat body = core::classMask(labels, movable);
    if (erosion > 0 && cv::countNonZero(body) > 0)
        cv::erode(body, body,
                  cv::getStructuringElement(cv::MORPH_RECT, {2 * erosion + 1, 2 * erosion + 1}),
                  {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(255));
    return body;
}

/// The median depth of each region (connected component) of `regions` over the sample grid
/// (0 where it has none).
std::vector<float> regionMedianDepths(const cv::Mat& regions, int count, const cv::Mat& depth)
{
    std::vector<std::vector<float>> depths(static_cast<size_t>(count));
    for (int v = kStep / 2; v < regions.rows; v += kStep)
    {
        for (int u = kStep / 2; u < regions.cols; u += kStep)
        {
            const int r = regions.at<int>(v, u);
            const float z = depth.at<float>(v, u);
            if (r > 0 && z > 0.0F)
                depths[static_cast<size_t>(r)].push_back(z);
        }
    }
    std::vector<float> medians(depths.size(), 0.0F);
    for (size_t r = 0; r < depths.size(); ++r)
    {
        auto& d = depths[r];
        if (d.empty())
            continue;
        std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
        medians[r] = d[d.size() / 2];
    }
    return medians;
}
}  // namespace

std::vector<Eigen::Vector3f> BodyVoxels::samples(const maps::BackProjector::Images& images,
                                                 const core::PinholeCamera& camera,
                                                 const std::vector<bool>& movable, int erosion)
{
    std::vector<Eigen::Vector3f> out;
    if (images.labels.empty() || images.depth.empty())
        return out;
    const cv::Mat inside = movableInside(images.labels, movable, erosion);
    if (cv::countNonZero(inside) == 0)  // no movable object: most keyframes
        return out;
    cv::Mat regions;
    const int count = cv::connectedComponents(inside, regions, 8, CV_32S);
    const std::vector<float> medians = regionMedianDepths(regions, count, images.depth);
    for (int v = kStep / 2; v < regions.rows; v += kStep)
    {
        for (int u = kStep / 2; u < regions.cols; u += kStep)
        {
            const int r = regions.at<int>(v, u);
            const float z = images.depth.at<float>(v, u);
            if (r > 0 && z > 0.0F && std::abs(z - medians[static_cast<size_t>(r)]) <= kDepthSpan)
                out.push_back(camera.unproject(u, v, z).cast<float>());
        }
    }
    return out;
}

BodyVoxels::BodyVoxels(double radius, double span_s) : radius_(radius), span_s_(span_s) {}

int64_t BodyVoxels::cell(float a) const
{
    return static_cast<int64_t>(std::floor(a / radius_));
}

void BodyVoxels::add(const KeyFrameContribution& c)
{
    for (const auto& b : c.bodies_cam)
    {
        double x = 0, y = 0, z = 0;
        c.T_world_cam.composePoint(b.x(), b.y(), b.z(), x, y, z);
        const Eigen::Vector3f w(static_cast<float>(x), static_cast<float>(y),
                                static_cast<float>(z));
        const int64_t cx = cell(w.x()), cy = cell(w.y()), cz = cell(w.z());
        auto& samples = cells_[voxelKey(cx, cy, cz)];
        if (samples.empty())
            addReach(cx, cy, cz);
        samples.push_back({w, c.timestamp});
    }
}

void BodyVoxels::addReach(int64_t cx, int64_t cy, int64_t cz)
{
    for (int64_t dx = -1; dx <= 1; ++dx)
    {
        for (int64_t dy = -1; dy <= 1; ++dy)
        {
            for (int64_t dz = -1; dz <= 1; ++dz)
                reach_.insert(voxelKey(cx + dx, cy + dy, cz + dz));
        }
    }
}

bool BodyVoxels::near(const Eigen::Vector3f& p) const
{
    // The voxel edge is the radius: every sample within it lies in the 27 voxels around p's.
    const auto r2 = static_cast<float>(radius_ * radius_);
    const int64_t cx = cell(p.x()), cy = cell(p.y()), cz = cell(p.z());
    if (reach_.count(voxelKey(cx, cy, cz)) == 0)
        return false;
    double first = std::numeric_limits<double>::infinity();
    double last = -first;
    for (int64_t dx = -1; dx <= 1; ++dx)
    {
        for (int64_t dy = -1; dy <= 1; ++dy)
        {
            for (int64_t dz = -1; dz <= 1; ++dz)
            {
                const auto it = cells_.find(voxelKey(cx + dx, cy + dy, cz + dz));
                if (it == cells_.end())
                    continue;
                for (const auto& s : it->second)
                {
                    if ((s.position - p).squaredNorm() > r2)
                        continue;
                    first = std::min(first, s.time);
                    last = std::max(last, s.time);
                    if (core::reached(last - first, span_s_))
                        return true;
                }
            }
        }
    }
    return false;
}
}  // namespace smap::mapping
