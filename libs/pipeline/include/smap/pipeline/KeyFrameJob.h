// A keyframe on its way from tracking to the segmentation + mapping worker.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <vector>

#include "smap/core/RgbdFrame.h"
#include "smap/mapping/DynamicRegionFinder.h"

namespace smap::pipeline
{
struct KeyFrameJob
{
    uint64_t keyframe = 0;  ///< the SLAM keyframe id (slam::KeyFrame::id())
    uint64_t frameId = 0;   ///< the tracker's number of the frame it was made from
    core::RgbdFrame frame;
    mrpt::poses::CPose3D T_world_cam;  ///< the tracked pose when the keyframe was made
    /// S of Algorithm 1: the keypoints the dynamic filter flagged, with their depth.
    std::vector<mapping::DynamicPoint> dynamicPoints;
};
}  // namespace smap::pipeline
