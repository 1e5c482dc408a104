// Motion-only bundle adjustment: the camera pose of a frame from its map point matches, with a
// robust (Huber) cost and rounds of chi-square outlier rejection (ORB-SLAM's PoseOptimization).
#pragma once

namespace smap::slam
{
struct Frame;

/// Refines frame.T_cam_world from its matches (map point positions are read, so hold the map
/// mutex) and sets frame.outlier. Returns the number of inliers; the pose is left unchanged
/// when there are fewer than 3 matches.
int optimizePose(Frame& frame, int rounds, int iterations);
}  // namespace smap::slam
