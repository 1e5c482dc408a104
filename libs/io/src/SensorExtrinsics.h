// How MRPT's CObservation3DRangeScan states where its two cameras are, and the optical-frame
// extrinsic (T_colour_depth) the rest of semantic-mapper uses. Private to libs/io: the rawlog
// reader and the TUM-to-rawlog converter must agree on it.
//
// MRPT: the observation's origin is the depth camera in MRPT's sensor frame (x forward, y left,
// z up); relativePoseIntensityWRTDepth is the pose of the colour camera's OPTICAL frame (x right,
// y down, z forward) in it. Both cameras at one place: the pure rotation opticalInSensorFrame().
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>

namespace smap::io
{
/// Pose of an optical camera frame in MRPT's sensor frame (yaw -90 deg, roll -90 deg).
mrpt::poses::CPose3D opticalInSensorFrame();

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p);
mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T);

/// T_colour_depth (depth optical frame -> colour optical frame) of an observation.
Eigen::Isometry3d colourFromDepth(const mrpt::poses::CPose3D& relativePoseIntensityWRTDepth);
/// The relativePoseIntensityWRTDepth that states `T_colour_depth`.
mrpt::poses::CPose3D relativePoseIntensityWRTDepth(const Eigen::Isometry3d& T_colour_depth);
}  // namespace smap::io
