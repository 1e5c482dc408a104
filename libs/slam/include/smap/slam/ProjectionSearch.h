// Matching map points to keypoints by projecting them with a predicted pose and comparing
// descriptors within a window (ORB-SLAM's SearchByProjection and Fuse).
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "smap/core/PinholeCamera.h"

namespace smap::slam
{
class KeyFrame;
class MapPoint;
struct Frame;

/// Descriptor distance thresholds for 256-bit ORB descriptors.
constexpr int kDescriptorHigh = 100;
constexpr int kDescriptorLow = 50;

/// The projection of a world point into a camera; false when behind it or outside the image.
bool projectIntoImage(const Eigen::Isometry3d& T_cam_world, const core::PinholeCamera& camera,
                      const Eigen::Vector3d& p_world, Eigen::Vector3d& p_cam, Eigen::Vector2d& uv);

/// Last frame's matched points into `current` (its T_cam_world is the prediction). The window
/// is `radius` px times the scale of the last observation's level. Returns new matches.
int searchFromLastFrame(Frame& current, const Frame& last, double radius);

/// Local map points into `frame`, skipping those it matched already; counts the points as
/// "visible" when they fall in the view frustum. The window is `radius` times a view-angle
/// factor times the predicted level's scale. Returns new matches.
int searchLocalPoints(Frame& frame, const std::vector<std::shared_ptr<MapPoint>>& points,
                      double radius);

/// A keyframe's map points into `frame` (relocalisation), skipping points it matched already.
int searchKeyFramePoints(Frame& frame, const KeyFrame& kf, double radius, int max_distance);

/// The keypoint of `kf` that `mp`, seen from `T_cam_world`, projects onto with a similar
/// descriptor (within `radius` px times its predicted level's scale, the reprojection error
/// within the chi-square bound, at most kDescriptorLow bits), or -1.
int matchProjectedPoint(const KeyFrame& kf, const Eigen::Isometry3d& T_cam_world,
                        const MapPoint& mp, double radius);

/// True when `p_world` projects onto keypoint `j` of `kf` (in front of it) within the chi-square
/// bound at the keypoint's level: pixel error, and virtual right column too where it has depth.
bool agreesWithKeypoint(const KeyFrame& kf, size_t j, const Eigen::Vector3d& p_world);

/// The keypoint of `kf` that a point seen elsewhere at `p_world` (pyramid `level`, `descriptor`)
/// projects onto and that has no map point yet: usable and shown static, with depth that agrees
/// (pixel and disparity error within the chi-square bound at its level), within `radius` px
/// times the level's scale, at most kDescriptorLow bits and below `ratio` times the runner-up's
/// distance. -1 when there is none.
int matchFreeKeypoint(const KeyFrame& kf, const Eigen::Vector3d& p_world, int level,
                      const uint8_t* descriptor, double radius, double ratio);

/// Projects `points` into `kf`; a point that lands on a keypoint with a similar descriptor
/// either becomes its observation or, when the keypoint has a point already, the two are fused
/// (the one with fewer observations is replaced). Returns the number fused or added.
int fuse(KeyFrame& kf, const std::vector<std::shared_ptr<MapPoint>>& points, double radius);
}  // namespace smap::slam
