#include "smap/sim/SpriteBillboard.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace smap::sim
{
namespace
{
constexpr uint8_t kOpaque = 128;       ///< alpha from which a texel is the person
constexpr double kMinMotion = 1e-3;    ///< metres: a surface point moving more is dynamic
constexpr double kNearest = 0.05;      ///< metres: billboards closer to the camera are not drawn
constexpr double kReliefWidth = 0.15;  ///< metres: rows at least this half-wide bulge fully
constexpr int kIterations = 4;         ///< fixed-point steps onto a surface with relief or lean

/// Bilinear sample of a CV_32FC4 texture at sprite coordinates (a, b).
cv::Vec4f bilinear(const cv::Mat& tex, double a, double b)
{
    const double x = std::clamp(a * tex.cols - 0.5, 0.0, tex.cols - 1.0);
    const double y = std::clamp(b * tex.rows - 0.5, 0.0, tex.rows - 1.0);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, tex.cols - 1), y1 = std::min(y0 + 1, tex.rows - 1);
    const auto fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
    const cv::Vec4f top = tex.at<cv::Vec4f>(y0, x0) * (1.0f - fx) + tex.at<cv::Vec4f>(y0, x1) * fx;
    const cv::Vec4f bottom =
        tex.at<cv::Vec4f>(y1, x0) * (1.0f - fx) + tex.at<cv::Vec4f>(y1, x1) * fx;
    return top * (1.0f - fy) + bottom * fy;
}

/// `premultiplied` (colour x alpha, alpha in [0, 1]) over `background`.
cv::Vec3b over(const cv::Vec4f& premultiplied, const cv::Vec3b& background)
{
    const float keep = 1.0f - premultiplied[3];
    cv::Vec3b out;
    for (int k = 0; k < 3; k++)
        out[k] = cv::saturate_cast<uint8_t>(premultiplied[k] + keep * background[k]);
    return out;
}
}  // namespace

/// The camera pose and the billboard's plane in camera coordinates, shared by every pixel.
struct SpriteBillboard::View
{
    Eigen::Matrix3d R;     ///< R_world_cam
    Eigen::Vector3d c;     ///< camera centre in the world
    Eigen::Vector3d nCam;  ///< the billboard's normal in camera coordinates
    double planeD = 0.0;   ///< nCam . X for camera points X on the plane through the feet

    View(const BillboardPose& pose, const mrpt::poses::CPose3D& T_world_cam)
        : R(T_world_cam.getRotationMatrix().asEigen()),
          c(T_world_cam.x(), T_world_cam.y(), T_world_cam.z()),
          nCam(R.transpose() * pose.normal),
          planeD(nCam.dot(R.transpose() * (pose.feet - c)))
    {
    }
};

SpriteBillboard::SpriteBillboard(cv::Mat bgra, BillboardStyle style)
    : sprite_(std::move(bgra)), style_(style)
{
    if (sprite_.type() != CV_8UC4 || sprite_.empty())
        throw std::invalid_argument("SpriteBillboard needs a non-empty CV_8UC4 (BGRA) sprite");
    if (style_.filtered)
    {
        // Colour times alpha, alpha in [0, 1]: what area filtering and blending work on.
        sprite_.convertTo(premultiplied_, CV_32FC4);
        for (auto it = premultiplied_.begin<cv::Vec4f>(); it != premultiplied_.end<cv::Vec4f>();
             ++it)
        {
            const float alpha = (*it)[3] / 255.0f;
            *it = cv::Vec4f((*it)[0] * alpha, (*it)[1] * alpha, (*it)[2] * alpha, alpha);
        }
    }
    rowExtents_.resize(static_cast<size_t>(sprite_.rows), {1.0f, 0.0f});
    for (int r = 0; r < sprite_.rows; r++)
    {
        int left = -1, right = -1;
        for (int c = 0; c < sprite_.cols; c++)
        {
            if (sprite_.at<cv::Vec4b>(r, c)[3] >= kOpaque)
            {
                left = left < 0 ? c : left;
                right = c;
            }
        }
        if (left >= 0)
            rowExtents_[static_cast<size_t>(r)] = {static_cast<float>(left) / sprite_.cols,
                                                   static_cast<float>(right + 1) / sprite_.cols};
    }
}

double SpriteBillboard::offsetAlongNormal(const BillboardPose& pose, double a, double b) const
{
    const double y = (1.0 - b) * pose.height;
    double offset = std::max(0.0, y - pose.pivotHeight) * std::tan(pose.leanTowards);
    if (style_.reliefDepth <= 0.0 || b < 0.0 || b >= 1.0)
        return offset;
    const auto& [left, right] = rowExtents_[static_cast<size_t>(
        std::min(sprite_.rows - 1, static_cast<int>(b * sprite_.rows)))];
    const double half = 0.5 * (right - left);
    if (half <= 0.0)
        return offset;
    const double t = (a - 0.5 * (left + right)) / half;
    if (std::abs(t) >= 1.0)
        return offset;
    const double halfMetres = half * pose.height * aspect();
    const double depth = style_.reliefDepth * std::min(1.0, halfMetres / kReliefWidth);
    return offset + depth * std::sqrt(1.0 - t * t);
}

Eigen::Vector3d SpriteBillboard::surfacePoint(const BillboardPose& pose, double a, double b) const
{
    const double width = pose.height * aspect();
    const double y = (1.0 - b) * pose.height;
    const double above = std::max(0.0, y - pose.pivotHeight);
    const double x = (a - 0.5) * width + above * std::tan(pose.leanAcross);
    return pose.feet + x * pose.across() + y * pose.up +
           offsetAlongNormal(pose, a, b) * pose.normal;
}

bool SpriteBillboard::imageBox(const BillboardPose& pose, const View& view,
                               const core::PinholeCamera& cam, cv::Rect& box) const
{
    const double width = pose.height * aspect();
    const Eigen::Vector3d across = pose.across();
    int u0 = cam.width, v0 = cam.height, u1 = -1, v1 = -1;
    bool behind = false;
    for (double a : {-0.5, 0.5})
    {
        for (double b : {0.0, 1.0})
        {
            // The sprite's corners as leaned, and the same pushed out by the relief.
            const double y = b * pose.height;
            const double above = std::max(0.0, y - pose.pivotHeight);
            const Eigen::Vector3d corner =
                pose.feet + (a * width + above * std::tan(pose.leanAcross)) * across + y * pose.up +
                above * std::tan(pose.leanTowards) * pose.normal;
            for (const double out : {0.0, style_.reliefDepth})
            {
                const Eigen::Vector3d X =
                    view.R.transpose() * (corner + out * pose.normal - view.c);
                if (X.z() <= kNearest)
                {
                    behind = true;
                    continue;
                }
                const Eigen::Vector2d uv = cam.project(X);
                u0 = std::min(u0, static_cast<int>(std::floor(uv.x())));
                u1 = std::max(u1, static_cast<int>(std::ceil(uv.x())));
                v0 = std::min(v0, static_cast<int>(std::floor(uv.y())));
                v1 = std::max(v1, static_cast<int>(std::ceil(uv.y())));
            }
        }
    }
    u0 = std::max(u0, 0);
    v0 = std::max(v0, 0);
    u1 = std::min(u1, cam.width - 1);
    v1 = std::min(v1, cam.height - 1);
    if (behind || u0 > u1 || v0 > v1)
        return false;
    box = cv::Rect(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
    return true;
}

bool SpriteBillboard::intersect(const BillboardPose& pose, const View& view,
                                const core::PinholeCamera& cam, int u, int v, Hit& hit) const
{
    // Ray through the pixel centre with z = 1: the depth of a point on it is s. A flat, upright
    // billboard is one plane intersection; relief and lean move the surface along the normal,
    // found by a few fixed-point steps from the plane.
    const Eigen::Vector3d d((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
    const double denom = view.nCam.dot(d);
    if (std::abs(denom) < 1e-9)
        return false;
    const bool curved = style_.reliefDepth > 0.0 || pose.leanTowards != 0.0;
    const double width = pose.height * aspect();
    const double tanAcross = std::tan(pose.leanAcross);
    const Eigen::Vector3d across = pose.across();
    double offset = 0.0;
    for (int step = 0; step < (curved ? kIterations : 1); step++)
    {
        hit.depth = (view.planeD + offset) / denom;
        const Eigen::Vector3d Xw = view.R * (hit.depth * d) + view.c - pose.feet;
        const double y = pose.up.dot(Xw);
        hit.a = (across.dot(Xw) - std::max(0.0, y - pose.pivotHeight) * tanAcross) / width + 0.5;
        hit.b = 1.0 - y / pose.height;
        hit.world = Xw + pose.feet;
        if (curved)
            offset = offsetAlongNormal(pose, hit.a, hit.b);
    }
    return hit.depth > kNearest && hit.a >= 0 && hit.a < 1 && hit.b >= 0 && hit.b < 1;
}

cv::Mat SpriteBillboard::filteredTexture(int heightPixels) const
{
    if (heightPixels >= premultiplied_.rows)
        return premultiplied_;
    const double scale = static_cast<double>(heightPixels) / premultiplied_.rows;
    const cv::Size size(std::max(1, static_cast<int>(std::lround(premultiplied_.cols * scale))),
                        std::max(1, heightPixels));
    cv::Mat scaled;
    cv::resize(premultiplied_, scaled, size, 0, 0, cv::INTER_AREA);
    return scaled;
}

cv::Vec4f SpriteBillboard::texel(const cv::Mat& texture, double a, double b) const
{
    if (style_.filtered)
        return bilinear(texture, a, b);
    const auto& px = sprite_.at<cv::Vec4b>(static_cast<int>(b * sprite_.rows),
                                           static_cast<int>(a * sprite_.cols));
    return {static_cast<float>(px[0]), static_cast<float>(px[1]), static_cast<float>(px[2]),
            px[3] / 255.0f};
}

void SpriteBillboard::draw(const BillboardPose& pose, const BillboardPose* before,
                           const core::PinholeCamera& cam, const mrpt::poses::CPose3D& T_world_cam,
                           uint8_t label, uint16_t instanceId, BillboardLayers& layers) const
{
    const View view(pose, T_world_cam);
    cv::Rect box;
    if (!imageBox(pose, view, cam, box))
        return;
    const cv::Mat texture = style_.filtered ? filteredTexture(box.height) : cv::Mat();
    for (int v = box.y; v < box.y + box.height; v++)
    {
        for (int u = box.x; u < box.x + box.width; u++)
        {
            Hit hit;
            if (!intersect(pose, view, cam, u, v, hit))
                continue;
            float& z = layers.depth.at<float>(v, u);
            const auto zs = static_cast<float>(hit.depth);
            if (z > 0.0f && z < zs)
                continue;  // a surface or a person nearer hides this one
            const cv::Vec4f t = texel(texture, hit.a, hit.b);
            auto& colour = layers.colour.at<cv::Vec3b>(v, u);
            if (style_.filtered && t[3] > 0.0f)
                colour = over(t, colour);  // the soft edge too
            if (t[3] * 255.0f < kOpaque)
                continue;
            if (!style_.filtered)
                colour = {static_cast<uint8_t>(t[0]), static_cast<uint8_t>(t[1]),
                          static_cast<uint8_t>(t[2])};
            z = zs;
            layers.labels.at<uint8_t>(v, u) = label;
            layers.instances.at<uint16_t>(v, u) = instanceId;
            const bool moved =
                before == nullptr ||
                (surfacePoint(*before, hit.a, hit.b) - hit.world).norm() > kMinMotion;
            layers.dynamic.at<uint8_t>(v, u) = moved ? 255 : 0;
        }
    }
}
}  // namespace smap::sim
