#include "SensorExtrinsics.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/math/CMatrixFixed.h>

namespace smap::io
{
mrpt::poses::CPose3D opticalInSensorFrame()
{
    return mrpt::poses::CPose3D(0, 0, 0, mrpt::DEG2RAD(-90.0), 0, mrpt::DEG2RAD(-90.0));
}

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = p.getRotationMatrix().asEigen();
    T.translation() = Eigen::Vector3d(p.x(), p.y(), p.z());
    return T;
}

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T)
{
    mrpt::math::CMatrixDouble33 R;
    R.asEigen() = T.linear();
    return mrpt::poses::CPose3D(
        R, mrpt::math::CVectorFixedDouble<3>(
               {T.translation().x(), T.translation().y(), T.translation().z()}));
}

Eigen::Isometry3d colourFromDepth(const mrpt::poses::CPose3D& relativePoseIntensityWRTDepth)
{
    // T_sensor_colour = relativePose, T_sensor_depthOptical = opticalInSensorFrame():
    // T_colour_depth = inverse(T_sensor_colour) * T_sensor_depthOptical.
    return toIsometry((-relativePoseIntensityWRTDepth) + opticalInSensorFrame());
}

mrpt::poses::CPose3D relativePoseIntensityWRTDepth(const Eigen::Isometry3d& T_colour_depth)
{
    return opticalInSensorFrame() + toCPose3D(T_colour_depth.inverse());
}
}  // namespace smap::io
