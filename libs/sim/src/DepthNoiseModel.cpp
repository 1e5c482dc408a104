#include "smap/sim/DepthNoiseModel.h"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace smap::sim
{
cv::Mat DepthNoiseModel::apply(const cv::Mat& depth, const cv::Mat& colour,
                               const core::PinholeCamera& camera, std::mt19937& rng) const
{
    cv::Mat out = depth.clone();
    if (!enabled)
        return out;
    cv::Mat grey;
    cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const double fb = camera.fx * baseline;
    auto at = [&](int v, int u)
    { return depth.at<float>(std::clamp(v, 0, depth.rows - 1), std::clamp(u, 0, depth.cols - 1)); };
    for (int v = 0; v < depth.rows; v++)
    {
        for (int u = 0; u < depth.cols; u++)
        {
            const double z = depth.at<float>(v, u);
            float& o = out.at<float>(v, u);
            if (!(z > 0.0) || z < minRange || z > maxRange)
            {
                o = 0.0f;
                continue;
            }
            // Silhouettes: a neighbour much nearer or farther.
            double jump = 0.0;
            for (const auto& [dv, du] :
                 {std::pair{0, 1}, {0, -1}, {1, 0}, {-1, 0}, {1, 1}, {-1, -1}})
            {
                const double n = at(v + dv, u + du);
                if (n > 0.0)
                    jump = std::max(jump, std::abs(n - z));
            }
            if (jump > 0.04 * z && uni(rng) < holeProbabilityEdges)
            {
                o = 0.0f;
                continue;
            }
            if (grey.at<uint8_t>(v, u) < 25 && uni(rng) < holeProbabilityDark)
            {
                o = 0.0f;
                continue;
            }
            // Grazing angle from the local surface normal (finite differences in 3D).
            const double zr = at(v, u + 1), zd = at(v + 1, u);
            if (zr > 0.0 && zd > 0.0)
            {
                const Eigen::Vector3d p = camera.unproject(u, v, z);
                const Eigen::Vector3d n =
                    (camera.unproject(u + 1, v, zr) - p).cross(camera.unproject(u, v + 1, zd) - p);
                if (n.norm() > 0.0 && std::abs(n.normalized().dot(p.normalized())) < grazingCosine)
                {
                    o = 0.0f;
                    continue;
                }
            }
            // Axial noise, then quantisation of the disparity the sensor measures.
            const double noisy = z + sigma(z) * gauss(rng);
            const double disparity = std::round(fb / noisy / subpixel) * subpixel;
            o = disparity > 0.0 ? static_cast<float>(fb / disparity) : 0.0f;
        }
    }
    return out;
}
}  // namespace smap::sim
