// Offscreen pictures of a semantic map (MRPT's CFBORender over EGL: no display needed): the
// map's points or voxels coloured by class or by RGB, seen from an orbit around the map's
// bounding box, with a legend of the classes present when coloured by class.
#pragma once

#include <opencv2/core/mat.hpp>
#include <set>

#include "smap/core/LabelSet.h"

namespace mrpt::opengl
{
class CSetOfObjects;
}

namespace smap::maps
{
class CSemanticOctoMap;
class CSemanticPointsMap;

struct SnapshotOptions
{
    int width = 800;
    int height = 600;
    double azimuth_deg = -60.0;   ///< orbit angle about the world z axis
    double elevation_deg = 40.0;  ///< above the xy plane
    double fov_deg = 45.0;        ///< vertical field of view
    /// Eye distance = this x the bounding box diagonal.
    double distance_factor = 1.1;
    bool legend = true;
    core::LabelSet labels = core::LabelSet::pascalVoc();  ///< legend names and colours
};

class MapSnapshot
{
public:
    explicit MapSnapshot(SnapshotOptions options = {});

    /// BGR image of the map as its render options colour it (by class: with a legend).
    cv::Mat render(const CSemanticPointsMap& map) const;
    cv::Mat render(const CSemanticOctoMap& map) const;

    /// Any visualization, with the given classes in the legend (empty: no legend).
    cv::Mat render(const mrpt::opengl::CSetOfObjects& objects, const std::set<int>& legend) const;

private:
    SnapshotOptions options_;
};
}  // namespace smap::maps
