#include "smap/pipeline/MapOutputWriter.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "smap/core/AtomicFile.h"

namespace fs = std::filesystem;

namespace smap::pipeline
{
namespace
{
void writePng(const std::string& path, const cv::Mat& image)
{
    core::writeFileAtomically(path,
                              [&](const std::string& tmp)
                              {
                                  if (!cv::imwrite(tmp, image))
                                      throw std::runtime_error("cannot write " + path);
                              });
}
}  // namespace

MapOutputWriter::MapOutputWriter(std::string directory, maps::SnapshotOptions snapshot)
    : dir_(std::move(directory)), snapshot_(std::move(snapshot))
{
    // The legend shows the background class in the grey the snapshots draw it in.
    std::vector<core::Label> labels = snapshot_.labels.labels();
    if (!labels.empty())
        labels[0].colourBgr = cv::Vec3b(190, 190, 190);
    snapshot_.labels = core::LabelSet(labels);
}

std::vector<std::string> MapOutputWriter::writeMaps(const mapping::SemanticMapBuilder& m) const
{
    std::vector<std::string> files;
    const fs::path dir(dir_);
    const auto& p = m.parameters();
    mrpt::maps::CMultiMetricMap multi;
    if (p.points_map)
    {
        m.pointsMap().savePly((dir / "semantic_points.ply").string());
        files.emplace_back("semantic_points.ply");
        multi.maps.push_back(std::make_shared<maps::CSemanticPointsMap>(m.pointsMap()));
    }
    if (p.octomap)
    {
        m.octoMap().saveOt((dir / "semantic_octomap.ot").string(), true);
        m.octoMap().saveBt((dir / "semantic_octomap.bt").string());
        files.emplace_back("semantic_octomap.ot");
        files.emplace_back("semantic_octomap.bt");
        multi.maps.push_back(std::make_shared<maps::CSemanticOctoMap>(m.octoMap()));
    }
    const std::string bin = (dir / "semantic_map.bin").string();
    core::writeFileAtomically(bin,
                              [&](const std::string& tmp)
                              {
                                  mrpt::io::CFileGZOutputStream out;
                                  if (!out.open(tmp, 1))
                                      throw std::runtime_error("cannot write " + bin);
                                  auto arch = mrpt::serialization::archiveFrom(out);
                                  arch << multi;
                              });
    files.emplace_back("semantic_map.bin");
    return files;
}

namespace
{
/// The map's own visualisation (a CPointCloudColoured), coloured by class, named `name`.
mrpt::opengl::CRenderizable::Ptr byClassCloud(const mrpt::maps::CMetricMap& map,
                                              const std::string& name, float pointSize)
{
    mrpt::opengl::CSetOfObjects objects;
    map.getVisualizationInto(objects);
    for (const auto& o : objects)
    {
        if (auto cloud = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(o))
        {
            cloud->setName(name);
            cloud->setPointSize(pointSize);
            return cloud;
        }
    }
    throw std::logic_error(name + ": the map drew no point cloud");
}

mrpt::opengl::CSetOfLines::Ptr trajectoryLines(const core::Trajectory& trajectory)
{
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setName("trajectory");
    lines->setLineWidth(3.0F);
    lines->setColor_u8(255, 0, 255);
    for (size_t i = 1; i < trajectory.size(); ++i)
    {
        const auto& a = trajectory[i - 1].T_world_cam;
        const auto& b = trajectory[i].T_world_cam;
        lines->appendLine(a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
    }
    return lines;
}
}  // namespace

std::string MapOutputWriter::writeScene(const mapping::SemanticMapBuilder& m,
                                        const core::Trajectory& trajectory) const
{
    // The map frame is the first camera's optical frame (x right, y down, z forward): turned
    // by -90 degrees about x, its "up" (-y) becomes the scene's z.
    auto world = mrpt::opengl::CSetOfObjects::Create();
    world->setName("world");
    world->setPose(mrpt::poses::CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(-90.0)));
    if (m.parameters().points_map)
    {
        maps::CSemanticPointsMap byClass = m.pointsMap();
        byClass.renderOptions.colour_by_class = true;
        world->insert(byClassCloud(byClass, "semantic_points", 2.0F));
    }
    if (m.parameters().octomap)
    {
        maps::CSemanticOctoMap byClass = m.octoMap();
        byClass.renderOptions.colour_by_class = true;
        auto voxels = byClassCloud(byClass, "semantic_octomap", 4.0F);
        voxels->setVisibility(!m.parameters().points_map);  // one map shown at a time
        world->insert(voxels);
    }
    world->insert(trajectoryLines(trajectory));
    mrpt::opengl::COpenGLScene scene;
    scene.insert(mrpt::opengl::CGridPlaneXY::Create(-5, 5, -5, 5, 0, 1));
    scene.insert(world);
    const std::string path = (fs::path(dir_) / "semantic_map.3Dscene").string();
    core::writeFileAtomically(path,
                              [&](const std::string& tmp)
                              {
                                  if (!scene.saveToFile(tmp))
                                      throw std::runtime_error("cannot write " + path);
                              });
    return "semantic_map.3Dscene";
}

std::vector<std::string> MapOutputWriter::writeSnapshots(const mapping::SemanticMapBuilder& m,
                                                         const core::Trajectory& trajectory) const
{
    const fs::path dir = fs::path(dir_) / "snapshots";
    fs::create_directories(dir);
    std::vector<std::string> files;
    const maps::MapSnapshot snapshot(snapshot_);
    // The scene turned upright ((x, y, z) -> (x, z, -y)); background-class points grey rather
    // than VOC black, so that the objects stand out.
    auto upright = [&](const mrpt::maps::CMetricMap& map, bool byClass, bool withTrajectory)
    {
        mrpt::opengl::CSetOfObjects objects;
        map.getVisualizationInto(objects);
        for (const auto& o : objects)
        {
            auto cloud = std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(o);
            if (!cloud)
                continue;
            for (size_t i = 0; i < cloud->size(); ++i)
            {
                const auto p = cloud->getPoint3Df(i);
                cloud->setPoint_fast(i, p.x, p.z, -p.y);
                uint8_t r = 0, g = 0, b = 0;
                cloud->getPointColor_fast(i, r, g, b);
                if (byClass && r == 0 && g == 0 && b == 0)
                    cloud->setPointColor_u8_fast(i, 190, 190, 190);
            }
        }
        if (withTrajectory && trajectory.size() > 1)
        {
            auto lines = mrpt::opengl::CSetOfLines::Create();
            lines->setLineWidth(3.0F);
            lines->setColor_u8(255, 0, 255);
            for (size_t i = 1; i < trajectory.size(); ++i)
            {
                const auto& a = trajectory[i - 1].T_world_cam;
                const auto& b = trajectory[i].T_world_cam;
                lines->appendLine(a.x(), a.z(), -a.y(), b.x(), b.z(), -b.y());
            }
            objects.insert(lines);
        }
        return objects;
    };
    auto legendOf = [](const std::vector<maps::SemanticPoint>& pts)
    {
        std::set<int> present;
        for (const auto& p : pts)
            present.insert(p.label);
        return present;
    };
    if (m.parameters().points_map && !m.pointsMap().isEmpty())
    {
        maps::CSemanticPointsMap byClass = m.pointsMap();
        byClass.renderOptions.colour_by_class = true;
        const auto legend = legendOf(byClass.points());
        writePng((dir / "map_by_class.png").string(),
                 snapshot.render(upright(byClass, true, false), legend));
        files.emplace_back("snapshots/map_by_class.png");
        maps::CSemanticPointsMap byColour = m.pointsMap();
        byColour.renderOptions.colour_by_class = false;
        writePng((dir / "map_by_colour.png").string(),
                 snapshot.render(upright(byColour, false, false), {}));
        files.emplace_back("snapshots/map_by_colour.png");
        writePng((dir / "trajectory.png").string(),
                 snapshot.render(upright(byColour, false, true), {}));
        files.emplace_back("snapshots/trajectory.png");
    }
    if (m.parameters().octomap && !m.octoMap().isEmpty())
    {
        maps::CSemanticOctoMap byClass = m.octoMap();
        byClass.renderOptions.colour_by_class = true;
        std::set<int> legend;
        for (const auto& v : byClass.occupiedVoxels())
            legend.insert(v.label == 255 ? 0 : v.label);
        writePng((dir / "octomap_by_class.png").string(),
                 snapshot.render(upright(byClass, true, false), legend));
        files.emplace_back("snapshots/octomap_by_class.png");
    }
    return files;
}
}  // namespace smap::pipeline
