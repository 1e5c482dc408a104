// The map files and pictures of a semantic-mapper run, each written atomically into the output
// folder:
//   semantic_map.bin        both maps in an mrpt::maps::CMultiMetricMap (MRPT serialization,
//                           gzip; readable by any program that links smap::maps)
//   semantic_points.ply     the point map (x y z r g b label confidence)
//   semantic_octomap.ot/.bt the octomap for octovis (colour by class) / occupancy only
//   semantic_map.3Dscene    an mrpt::opengl::COpenGLScene for MRPT's SceneViewer3D: both maps
//                           by class and the camera path, z up
//   snapshots/map_by_class.png, map_by_colour.png, octomap_by_class.png, trajectory.png
#pragma once

#include <string>
#include <vector>

#include "smap/core/Trajectory.h"
#include "smap/mapping/SemanticMapBuilder.h"
#include "smap/maps/MapSnapshot.h"

namespace smap::pipeline
{
class MapOutputWriter
{
public:
    MapOutputWriter(std::string directory, maps::SnapshotOptions snapshot);

    /// Returns the files written (relative to the folder).
    std::vector<std::string> writeMaps(const mapping::SemanticMapBuilder& maps) const;
    /// semantic_map.3Dscene (gzip, MRPT serialization), standard MRPT objects only, so that
    /// SceneViewer3D opens it without our plugin: "semantic_points" and "semantic_octomap"
    /// (CPointCloudColoured by class; the voxel centres), "trajectory" (CSetOfLines, one per
    /// step) inside "world", a CSetOfObjects turning the map frame (the first camera's
    /// optical frame, y down) upright; the maps the parameters turned off are left out.
    /// Returns the file written (relative to the folder).
    std::string writeScene(const mapping::SemanticMapBuilder& maps,
                           const core::Trajectory& trajectory) const;
    /// The snapshots, seen with the first camera's "up" (-y of the optical frame) as up; the
    /// trajectory picture draws the camera path over the map coloured by RGB.
    std::vector<std::string> writeSnapshots(const mapping::SemanticMapBuilder& maps,
                                            const core::Trajectory& trajectory) const;

private:
    std::string dir_;
    maps::SnapshotOptions snapshot_;
};
}  // namespace smap::pipeline
