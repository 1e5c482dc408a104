#include "smap/maps/CSemanticPointsMap.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/core/initializer.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/LabelSet.h"
#include "smap/maps/CObservationSemanticRGBD.h"
#include "smap/maps/CSemanticOctoMap.h"

IMPLEMENTS_SERIALIZABLE(CSemanticPointsMap, mrpt::maps::CMetricMap, smap::maps)

MAP_DEFINITION_REGISTER("semanticPointsMap,smap::maps::CSemanticPointsMap",
                        smap::maps::CSemanticPointsMap)

// MRPT's class registry (deserialization by class name, e.g. reading annotated rawlogs) learns
// our classes when this library is loaded, as MRPT's own libraries do.
MRPT_INITIALIZER(smap_maps_registerClasses)
{
    mrpt::rtti::registerClass(CLASS_ID(smap::maps::CSemanticPointsMap));
    mrpt::rtti::registerClass(CLASS_ID(smap::maps::CObservationSemanticRGBD));
    mrpt::rtti::registerClass(CLASS_ID(smap::maps::CSemanticOctoMap));
}

namespace smap::maps
{
// ---- options ----

void CSemanticPointsMap::TInsertionOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    voxel_size = cfg.read_double(section, "voxel_size", voxel_size);
    projection.min_depth = cfg.read_double(section, "min_depth", projection.min_depth);
    projection.max_depth = cfg.read_double(section, "max_depth", projection.max_depth);
    projection.stride = cfg.read_int(section, "stride", projection.stride);
    if (!(voxel_size >= 0.001 && voxel_size <= 10.0))
        throw core::InputError(mrpt::format("[%s] voxel_size = %g must be in [0.001, 10] m",
                                            section.c_str(), voxel_size));
    if (!(projection.max_depth > projection.min_depth) || projection.stride < 1)
        throw core::InputError(
            mrpt::format("[%s] need min_depth < max_depth and stride >= 1", section.c_str()));
}

void CSemanticPointsMap::TInsertionOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                                             const std::string& section) const
{
    cfg.write(section, "voxel_size", voxel_size);
    cfg.write(section, "min_depth", projection.min_depth);
    cfg.write(section, "max_depth", projection.max_depth);
    cfg.write(section, "stride", projection.stride);
}

// ---- map definition (CMultiMetricMap) ----

CSemanticPointsMap::TMapDefinition::TMapDefinition() = default;

void CSemanticPointsMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& prefix)
{
    insertionOpts.loadFromConfigFile(source, prefix + "_insertOpts");
    renderOpts.loadFromConfigFile(source, prefix + "_renderOpts");
}

void CSemanticPointsMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    insertionOpts.dumpToTextStream(out);
    renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CSemanticPointsMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    const auto& d = dynamic_cast<const TMapDefinition&>(def);
    auto* m = new CSemanticPointsMap();
    m->insertionOptions = d.insertionOpts;
    m->renderOptions = d.renderOpts;
    return m;
}

// ---- voxels ----

void CSemanticPointsMap::Voxel::add(const SemanticPoint& p)
{
    for (int k = 0; k < 3; k++)
        sum[k] += p.position[k];
    rgb[0] += p.r;
    rgb[1] += p.g;
    rgb[2] += p.b;
    count++;
    // The label's summed confidence; a new label takes a free slot or the weakest one.
    size_t slot = labels.size();
    for (size_t i = 0; i < labels.size() && slot == labels.size(); i++)
        if (labels[i] == p.label)
            slot = i;
    if (slot == labels.size())
    {
        slot = static_cast<size_t>(std::min_element(scores.begin(), scores.end()) - scores.begin());
        for (size_t i = 0; i < labels.size(); i++)
            if (labels[i] == 255 && p.label != 255)
            {
                slot = i;
                break;
            }
        labels[slot] = p.label;
        scores[slot] = 0.0f;
    }
    scores[slot] += std::max(p.confidence, 1e-6f);
}

SemanticPoint CSemanticPointsMap::Voxel::mean() const
{
    SemanticPoint p;
    for (int k = 0; k < 3; k++)
        p.position[k] = static_cast<float>(sum[k] / count);
    p.r = static_cast<uint8_t>(rgb[0] / count);
    p.g = static_cast<uint8_t>(rgb[1] / count);
    p.b = static_cast<uint8_t>(rgb[2] / count);
    const auto best =
        static_cast<size_t>(std::max_element(scores.begin(), scores.end()) - scores.begin());
    float total = 0.0f;
    for (const float s : scores)
        total += s;
    p.label = labels[best];
    p.confidence = total > 0.0f ? scores[best] / total : 0.0f;
    return p;
}

uint64_t CSemanticPointsMap::keyOf(const Eigen::Vector3f& p) const
{
    // 21 bits per axis around the origin: +-2^20 voxels (20 km at 2 cm).
    uint64_t key = 0;
    for (int k = 0; k < 3; k++)
    {
        const auto i = static_cast<int64_t>(std::floor(p[k] / insertionOptions.voxel_size));
        key |=
            (static_cast<uint64_t>(std::clamp<int64_t>(i, -(1 << 20), (1 << 20) - 1) + (1 << 20)) &
             0x1FFFFF)
            << (21 * k);
    }
    return key;
}

void CSemanticPointsMap::insertPoints(const std::vector<SemanticPoint>& points)
{
    for (const auto& p : points)
        voxels_[keyOf(p.position)].add(p);
}

size_t CSemanticPointsMap::removeIf(const std::function<bool(const Eigen::Vector3f&)>& drop)
{
    size_t removed = 0;
    for (auto it = voxels_.begin(); it != voxels_.end();)
    {
        if (drop(it->second.mean().position))
        {
            it = voxels_.erase(it);
            ++removed;
        }
        else
            ++it;
    }
    return removed;
}

std::vector<SemanticPoint> CSemanticPointsMap::points() const
{
    std::vector<std::pair<uint64_t, const Voxel*>> order;
    order.reserve(voxels_.size());
    for (const auto& [key, v] : voxels_)
        order.emplace_back(key, &v);
    std::sort(order.begin(), order.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<SemanticPoint> out;
    out.reserve(order.size());
    for (const auto& [key, v] : order)
        out.push_back(v->mean());
    return out;
}

bool CSemanticPointsMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const auto* o = dynamic_cast<const CObservationSemanticRGBD*>(&obs);
    if (!o)
        return false;
    const mrpt::poses::CPose3D T_world_cam = o->cameraPose(robotPose);
    const auto points = o->staticPoints(T_world_cam, insertionOptions.projection);
    insertPoints(points);
    return true;
}

// ---- files ----

void CSemanticPointsMap::savePly(const std::string& path) const
{
    const auto pts = points();
    core::writeFileAtomically(
        path,
        [&](const std::string& tmp)
        {
            std::ofstream f(tmp, std::ios::binary);
            f << "ply\nformat binary_little_endian 1.0\n"
              << "comment semantic-mapper CSemanticPointsMap, voxel " << insertionOptions.voxel_size
              << " m\n"
              << "element vertex " << pts.size() << "\n"
              << "property float x\nproperty float y\nproperty float z\n"
              << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              << "property uchar label\nproperty float confidence\nend_header\n";
            for (const auto& p : pts)
            {
                const float xyz[3] = {p.position.x(), p.position.y(), p.position.z()};
                const uint8_t c[4] = {p.r, p.g, p.b, p.label};
                f.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
                f.write(reinterpret_cast<const char*>(c), sizeof c);
                f.write(reinterpret_cast<const char*>(&p.confidence), sizeof p.confidence);
            }
            if (!f)
                throw std::runtime_error("cannot write " + path);
        });
}

void CSemanticPointsMap::loadPly(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    if (!f)
        throw core::InputError("cannot open PLY '" + path + "'");
    std::string line, expected;
    size_t count = 0;
    bool binary = false;
    std::vector<std::string> properties;
    while (std::getline(f, line) && line != "end_header")
    {
        std::istringstream ss(line);
        std::string word;
        ss >> word;
        if (word == "format")
            binary = line == "format binary_little_endian 1.0";
        else if (word == "element")
        {
            std::string name;
            ss >> name >> count;
        }
        else if (word == "property")
        {
            std::string type, name;
            ss >> type >> name;
            type += " ";
            type += name;
            properties.push_back(type);
        }
    }
    const std::vector<std::string> ours = {"float x",     "float y",         "float z",
                                           "uchar red",   "uchar green",     "uchar blue",
                                           "uchar label", "float confidence"};
    if (line != "end_header" || !binary || properties != ours)
        throw core::InputError("'" + path +
                               "' is not a PLY written by CSemanticPointsMap (binary x y z "
                               "red green blue label confidence)");
    clear();
    std::vector<SemanticPoint> pts(count);
    for (auto& p : pts)
    {
        float xyz[3];
        uint8_t c[4];
        f.read(reinterpret_cast<char*>(xyz), sizeof xyz);
        f.read(reinterpret_cast<char*>(c), sizeof c);
        f.read(reinterpret_cast<char*>(&p.confidence), sizeof p.confidence);
        p.position = {xyz[0], xyz[1], xyz[2]};
        p.r = c[0];
        p.g = c[1];
        p.b = c[2];
        p.label = c[3];
    }
    if (!f)
        throw core::InputError(
            mrpt::format("'%s' is truncated: fewer than %zu points", path.c_str(), count));
    insertPoints(pts);
}

void CSemanticPointsMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
    savePly(prefix + ".ply");
}

// ---- rendering, text ----

void CSemanticPointsMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const
{
    auto cloud = mrpt::opengl::CPointCloudColoured::Create();
    cloud->setPointSize(static_cast<float>(renderOptions.point_size));
    for (const auto& p : points())
    {
        cv::Vec3b bgr(p.b, p.g, p.r);
        if (renderOptions.colour_by_class)
            bgr = labels_.colourOf(p.label);
        cloud->push_back(p.position.x(), p.position.y(), p.position.z(), bgr[2] / 255.0f,
                         bgr[1] / 255.0f, bgr[0] / 255.0f);
    }
    o.insert(cloud);
}

std::string CSemanticPointsMap::asString() const
{
    return mrpt::format("CSemanticPointsMap: %zu voxels of %.3f m", voxels_.size(),
                        insertionOptions.voxel_size);
}

// ---- serialization ----

uint8_t CSemanticPointsMap::serializeGetVersion() const
{
    return 0;
}

void CSemanticPointsMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << insertionOptions.voxel_size << insertionOptions.projection.min_depth
        << insertionOptions.projection.max_depth
        << static_cast<int32_t>(insertionOptions.projection.stride) << renderOptions.colour_by_class
        << renderOptions.point_size;
    std::vector<std::pair<uint64_t, const Voxel*>> order;
    for (const auto& [key, v] : voxels_)
        order.emplace_back(key, &v);
    std::sort(order.begin(), order.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    out << static_cast<uint64_t>(order.size());
    for (const auto& [key, v] : order)
    {
        out << key << v->sum[0] << v->sum[1] << v->sum[2] << v->rgb[0] << v->rgb[1] << v->rgb[2]
            << v->count;
        for (size_t i = 0; i < v->labels.size(); i++)
            out << v->labels[i] << v->scores[i];
    }
}

void CSemanticPointsMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    int32_t stride = 1;
    in >> insertionOptions.voxel_size >> insertionOptions.projection.min_depth >>
        insertionOptions.projection.max_depth >> stride >> renderOptions.colour_by_class >>
        renderOptions.point_size;
    insertionOptions.projection.stride = stride;
    uint64_t n = 0;
    in >> n;
    voxels_.clear();
    voxels_.reserve(n);
    for (uint64_t i = 0; i < n; i++)
    {
        uint64_t key = 0;
        Voxel v;
        in >> key >> v.sum[0] >> v.sum[1] >> v.sum[2] >> v.rgb[0] >> v.rgb[1] >> v.rgb[2] >>
            v.count;
        for (size_t k = 0; k < v.labels.size(); k++)
            in >> v.labels[k] >> v.scores[k];
        voxels_[key] = v;
    }
}
}  // namespace smap::maps
