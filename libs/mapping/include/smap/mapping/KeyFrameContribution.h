// What one keyframe put into the maps: its static points in its own camera frame and the pose
// they were inserted at, kept so that a refined pose can re-anchor them.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/maps/BackProjector.h"

namespace smap::mapping
{
struct KeyFrameContribution
{
    uint64_t keyframe = 0;  ///< the SLAM keyframe's id (slam::KeyFrame::id())
    uint64_t frameId = 0;   ///< the tracker's number of the frame it was made from
    double timestamp = 0.0;
    mrpt::poses::CPose3D T_world_cam;             ///< the pose the points were inserted at
    std::vector<maps::SemanticPoint> points_cam;  ///< camera (optical) frame
    core::PinholeCamera camera;                   ///< the keyframe's camera
    /// Its static depth, nearest per cell of 8 x 8 pixels where it observed most of the cell
    /// (CV_32FC1, 0: not observed); empty unless [map] see_through_margin > 0.
    cv::Mat static_depth_cells;
    /// Where movers were: samples of the keyframe's dynamic pixels (M) with depth, camera frame.
    std::vector<Eigen::Vector3f> movers_cam;
    /// Where it saw bodies of movable-class objects: samples of the inside of its movable-class
    /// regions with depth, camera frame; empty unless [map] movable_body_radius > 0.
    std::vector<Eigen::Vector3f> bodies_cam;

    size_t memoryBytes() const
    {
        return sizeof(*this) + points_cam.capacity() * sizeof(maps::SemanticPoint) +
               (movers_cam.capacity() + bodies_cam.capacity()) * sizeof(Eigen::Vector3f) +
               static_depth_cells.total() * static_depth_cells.elemSize();
    }
};
}  // namespace smap::mapping
