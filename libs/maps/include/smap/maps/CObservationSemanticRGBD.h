// An RGB-D keyframe annotated for semantic mapping: colour, depth, labels (and the probability
// of each pixel's label), the dynamic mask of Algorithm 1, intrinsics and the camera's pose on
// the robot. Both semantic maps insert it; it is an MRPT CObservation, serializable, so
// annotated rawlogs store it and RawLogViewer lists it.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

#include "smap/core/PinholeCamera.h"
#include "smap/maps/BackProjector.h"

namespace smap::maps
{
class CObservationSemanticRGBD : public mrpt::obs::CObservation
{
    DEFINE_SERIALIZABLE(CObservationSemanticRGBD, smap::maps)

public:
    /// Pose of the camera's optical frame (x right, y down, z forward) on the robot; the
    /// pose the map inserts at is robotPose + sensorPose (robotPose = T_world_cam and
    /// sensorPose = identity when the observation comes from semantic-mapper).
    mrpt::poses::CPose3D sensorPose;
    core::PinholeCamera camera;
    cv::Mat colour;       ///< CV_8UC3 BGR
    cv::Mat depth;        ///< CV_32FC1 metres along +Z, 0 = none
    cv::Mat labels;       ///< CV_8UC1 class ids of the label set (255 = void)
    cv::Mat confidence;   ///< CV_32FC1 probability of each pixel's label (empty: 1)
    cv::Mat dynamicMask;  ///< CV_8UC1, 255 = dynamic (Algorithm 1's M; empty: none)

    /// Throws std::invalid_argument when images and camera disagree in size or type.
    void validate() const;

    /// The camera's pose in the world: robotPose (identity when absent) + sensorPose.
    mrpt::poses::CPose3D cameraPose(
        const std::optional<const mrpt::poses::CPose3D>& robotPose) const;
    /// The static pixels back-projected into the world (validates first): what a map inserts.
    std::vector<SemanticPoint> staticPoints(const mrpt::poses::CPose3D& T_world_cam,
                                            const BackProjectionParameters& params) const;

    void getSensorPose(mrpt::poses::CPose3D& out) const override { out = sensorPose; }
    void setSensorPose(const mrpt::poses::CPose3D& p) override { sensorPose = p; }
    void getDescriptionAsText(std::ostream& o) const override;
};
}  // namespace smap::maps
