// A person cut-out (RGBA sprite) drawn as a depth-consistent billboard: a vertical sprite standing
// on the floor and facing a viewer, optionally with a body-shaped relief towards the viewer and a
// lean of the part above a pivot height, drawn per pixel with a depth test into colour, depth,
// label, instance and dynamic images. The synthetic office's people and the people composited
// into real recordings are both drawn this way.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::sim
{
/// Where a billboard stands at one instant (world frame).
struct BillboardPose
{
    Eigen::Vector3d feet = Eigen::Vector3d::Zero();     ///< bottom centre of the sprite
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit, horizontal, towards the viewer
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();      ///< unit
    double height = 1.75;                               ///< metres, sprite bottom to top
    double pivotHeight = 0.0;  ///< metres above the feet; the part above leans
    double leanAcross = 0.0;   ///< rad, sideways lean above the pivot (in the sprite's plane)
    double leanTowards = 0.0;  ///< rad, lean above the pivot towards the viewer

    /// Unit vector across the sprite, left to right as the viewer sees it.
    Eigen::Vector3d across() const { return up.cross(normal).normalized(); }
};

struct BillboardStyle
{
    /// Metres: each sprite row bulges towards the viewer by up to this much, with an elliptic
    /// profile across the row's silhouette (narrow limbs less), so that the person has a body
    /// in depth rather than a flat cut-out. 0: flat.
    double reliefDepth = 0.0;
    /// true: the sprite is area-filtered to its size on screen, sampled bilinearly and its soft
    /// edge blended into the background; false: the nearest texel, hard edges.
    bool filtered = false;
};

/// The images a billboard is drawn into (views; all of the frame's size).
struct BillboardLayers
{
    cv::Mat colour;     ///< CV_8UC3
    cv::Mat depth;      ///< CV_32FC1 metres along +Z; 0 = nothing there
    cv::Mat labels;     ///< CV_8UC1
    cv::Mat instances;  ///< CV_16UC1; 0 = no person
    cv::Mat dynamic;    ///< CV_8UC1; 255 on moving pixels
};

class SpriteBillboard
{
public:
    /// `bgra`: CV_8UC4 with a non-empty alpha (>= 128 marks the person).
    SpriteBillboard(cv::Mat bgra, BillboardStyle style);

    /// Sprite width over height.
    double aspect() const { return static_cast<double>(sprite_.cols) / sprite_.rows; }
    const cv::Mat& sprite() const { return sprite_; }

    /// World point of sprite coordinates (a across [0, 1) left to right, b down [0, 1) top to
    /// bottom) for `pose`, relief and lean included.
    Eigen::Vector3d surfacePoint(const BillboardPose& pose, double a, double b) const;

    /// Draws the billboard seen from T_world_cam: pixels where the sprite's alpha is >= 128 and
    /// nothing nearer is drawn (a depth of 0 hides nothing) get the sprite's colour, their depth,
    /// `label` and `instanceId`; they are marked dynamic when their surface point moved more than
    /// 1 mm since `before` (null: always). Nothing is drawn when a corner of the billboard is
    /// behind the camera.
    void draw(const BillboardPose& pose, const BillboardPose* before,
              const core::PinholeCamera& cam, const mrpt::poses::CPose3D& T_world_cam,
              uint8_t label, uint16_t instanceId, BillboardLayers& layers) const;

private:
    struct View;
    struct Hit
    {
        double a = 0.0, b = 0.0;  ///< sprite coordinates
        double depth = 0.0;       ///< metres along the camera's +Z
        Eigen::Vector3d world;
    };
    /// Offset of a sprite point from the plane through the feet, along the normal.
    double offsetAlongNormal(const BillboardPose& pose, double a, double b) const;
    /// Pixel box holding the billboard; false when it is behind the camera or off the image.
    bool imageBox(const BillboardPose& pose, const View& view, const core::PinholeCamera& cam,
                  cv::Rect& box) const;
    /// The surface point on the ray through the centre of pixel (u, v); false when it misses.
    bool intersect(const BillboardPose& pose, const View& view, const core::PinholeCamera& cam,
                   int u, int v, Hit& hit) const;
    /// The premultiplied sprite, area-filtered down to `heightPixels` rows when smaller.
    cv::Mat filteredTexture(int heightPixels) const;
    /// BGR + alpha in [0, 1] at sprite coordinates: premultiplied and bilinear from `texture`
    /// when filtered, else the nearest texel of the sprite.
    cv::Vec4f texel(const cv::Mat& texture, double a, double b) const;

    cv::Mat sprite_;
    cv::Mat premultiplied_;  ///< CV_32FC4, made once when the style is filtered
    BillboardStyle style_;
    /// Per sprite row: left and right silhouette edge (alpha >= 128) as fractions of the width;
    /// left > right for rows without any.
    std::vector<std::pair<float, float>> rowExtents_;
};
}  // namespace smap::sim
