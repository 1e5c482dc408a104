#include "smap/maps/CSemanticOctoMap.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/ColorOcTree.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/core/LabelSet.h"
#include "smap/maps/CObservationSemanticRGBD.h"

IMPLEMENTS_SERIALIZABLE(CSemanticOctoMap, mrpt::maps::CMetricMap, smap::maps)

MAP_DEFINITION_REGISTER("semanticOctoMap,smap::maps::CSemanticOctoMap",
                        smap::maps::CSemanticOctoMap)

namespace smap::maps
{
namespace
{
uint64_t packKey(const octomap::OcTreeKey& k)
{
    return static_cast<uint64_t>(k[0]) | (static_cast<uint64_t>(k[1]) << 16) |
           (static_cast<uint64_t>(k[2]) << 32);
}

octomap::OcTreeKey unpackKey(uint64_t k)
{
    return octomap::OcTreeKey(static_cast<octomap::key_type>(k & 0xFFFF),
                              static_cast<octomap::key_type>((k >> 16) & 0xFFFF),
                              static_cast<octomap::key_type>((k >> 32) & 0xFFFF));
}
/// A deep copy. ColorOcTree's copy constructor is not one: OcTreeDataNode's copy constructor
/// re-creates the children as base nodes without colour (reading their colour then reads past
/// the allocation), so the tree goes through its own binary data stream instead.
std::unique_ptr<octomap::ColorOcTree> cloneTree(const octomap::ColorOcTree& tree)
{
    auto copy = std::make_unique<octomap::ColorOcTree>(tree.getResolution());
    copy->setProbHit(tree.getProbHit());
    copy->setProbMiss(tree.getProbMiss());
    copy->setClampingThresMin(tree.getClampingThresMin());
    copy->setClampingThresMax(tree.getClampingThresMax());
    copy->setOccupancyThres(tree.getOccupancyThres());
    std::stringstream data;
    tree.writeData(data);
    copy->readData(data);
    return copy;
}
}  // namespace

struct CSemanticOctoMap::Impl
{
    std::unique_ptr<octomap::ColorOcTree> tree;
    /// Normalised class log-probabilities of labelled voxels, by packed OcTreeKey.
    std::unordered_map<uint64_t, std::vector<float>> classes;
};

// ---- options ----

void CSemanticOctoMap::TInsertionOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    resolution = cfg.read_double(section, "resolution", resolution);
    projection.min_depth = cfg.read_double(section, "min_depth", projection.min_depth);
    projection.max_depth = cfg.read_double(section, "max_depth", projection.max_depth);
    if (standalone_keys)
    {
        projection.stride = cfg.read_int(section, "stride", projection.stride);
        label_count = cfg.read_int(section, "label_count", label_count);
    }
    prob_hit = cfg.read_double(section, "prob_hit", prob_hit);
    prob_miss = cfg.read_double(section, "prob_miss", prob_miss);
    clamping_min = cfg.read_double(section, "clamping_min", clamping_min);
    clamping_max = cfg.read_double(section, "clamping_max", clamping_max);
    label_log_floor = cfg.read_double(section, "label_log_floor", label_log_floor);
    if (!(resolution >= 0.005 && resolution <= 2.0))
        throw core::InputError(mrpt::format("[%s] resolution = %g must be in [0.005, 2] m",
                                            section.c_str(), resolution));
    if (!(prob_hit > 0.5 && prob_hit < 1.0) || !(prob_miss > 0.0 && prob_miss < 0.5) ||
        !(clamping_min > 0.0 && clamping_min < 0.5) || !(clamping_max > 0.5 && clamping_max < 1.0))
        throw core::InputError(mrpt::format(
            "[%s] need 0.5 < prob_hit < 1, 0 < prob_miss < 0.5, 0 < clamping_min < 0.5 < "
            "clamping_max < 1",
            section.c_str()));
    if (label_count < 1 || label_count > 255 || !(label_log_floor < 0.0))
        throw core::InputError(mrpt::format(
            "[%s] label_count must be in [1, 255] and label_log_floor < 0", section.c_str()));
    if (!(projection.max_depth > projection.min_depth) || projection.stride < 1)
        throw core::InputError(
            mrpt::format("[%s] need min_depth < max_depth and stride >= 1", section.c_str()));
}

void CSemanticOctoMap::TInsertionOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                                                           const std::string& section) const
{
    cfg.write(section, "resolution", resolution);
    cfg.write(section, "min_depth", projection.min_depth);
    cfg.write(section, "max_depth", projection.max_depth);
    if (standalone_keys)
        cfg.write(section, "stride", projection.stride);
    cfg.write(section, "prob_hit", prob_hit);
    cfg.write(section, "prob_miss", prob_miss);
    cfg.write(section, "clamping_min", clamping_min);
    cfg.write(section, "clamping_max", clamping_max);
    if (standalone_keys)
        cfg.write(section, "label_count", label_count);
    cfg.write(section, "label_log_floor", label_log_floor);
}

// ---- map definition ----

CSemanticOctoMap::TMapDefinition::TMapDefinition()
{
    renderOpts.point_size = 4.0;  // as CSemanticOctoMap's own default
}

void CSemanticOctoMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& prefix)
{
    insertionOpts.loadFromConfigFile(source, prefix + "_insertOpts");
    renderOpts.loadFromConfigFile(source, prefix + "_renderOpts");
}

void CSemanticOctoMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    insertionOpts.dumpToTextStream(out);
    renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CSemanticOctoMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& def)
{
    const auto& d = dynamic_cast<const TMapDefinition&>(def);
    auto* m = new CSemanticOctoMap();
    m->insertionOptions = d.insertionOpts;
    m->renderOptions = d.renderOpts;
    return m;
}

// ---- life cycle ----

CSemanticOctoMap::CSemanticOctoMap() : impl_(std::make_unique<Impl>())
{
    renderOptions.point_size = 4.0;  // voxels are sparser than the points map's points
}
CSemanticOctoMap::~CSemanticOctoMap() = default;

CSemanticOctoMap::CSemanticOctoMap(const CSemanticOctoMap& other)
    : CMetricMap(other),
      insertionOptions(other.insertionOptions),
      renderOptions(other.renderOptions),
      impl_(std::make_unique<Impl>())
{
    *this = other;
}

CSemanticOctoMap& CSemanticOctoMap::operator=(const CSemanticOctoMap& other)
{
    if (this == &other)
        return *this;
    insertionOptions = other.insertionOptions;
    renderOptions = other.renderOptions;
    labels_ = other.labels_;
    impl_->tree = other.impl_->tree ? cloneTree(*other.impl_->tree) : nullptr;
    impl_->classes = other.impl_->classes;
    return *this;
}

void CSemanticOctoMap::ensureTree()
{
    if (impl_->tree)
        return;
    impl_->tree = std::make_unique<octomap::ColorOcTree>(insertionOptions.resolution);
    impl_->tree->setProbHit(insertionOptions.prob_hit);
    impl_->tree->setProbMiss(insertionOptions.prob_miss);
    impl_->tree->setClampingThresMin(insertionOptions.clamping_min);
    impl_->tree->setClampingThresMax(insertionOptions.clamping_max);
}

void CSemanticOctoMap::internal_clear()
{
    impl_->tree.reset();
    impl_->classes.clear();
}

bool CSemanticOctoMap::isEmpty() const
{
    return !impl_->tree || impl_->tree->size() == 0;
}

void CSemanticOctoMap::setLabels(const core::LabelSet& labels)
{
    if (labels.empty())
        throw core::InputError("CSemanticOctoMap::setLabels: the label set is empty");
    labels_ = labels;
    insertionOptions.label_count = static_cast<int>(labels.size());
}

// ---- insertion ----

void CSemanticOctoMap::insertPoints(const std::vector<SemanticPoint>& points,
                                    const Eigen::Vector3f& sensorOrigin)
{
    ensureTree();
    auto& tree = *impl_->tree;
    // Occupancy: rays clear what they cross, end points get a hit (discretised: one ray and one
    // update per voxel and frame). Done here rather than with insertPointCloud, whose OpenMP
    // ray casting updates the voxels in a thread-dependent order (pruning, and so the tree and
    // its colours, would then differ between runs): the keys are updated in sorted order.
    const octomap::point3d origin(sensorOrigin.x(), sensorOrigin.y(), sensorOrigin.z());
    std::vector<uint64_t> hits;
    std::unordered_set<uint64_t> hitSet;
    std::unordered_set<uint64_t> freeSet;
    octomap::KeyRay ray;
    for (const auto& p : points)
    {
        const octomap::OcTreeKey key =
            tree.coordToKey(p.position.x(), p.position.y(), p.position.z());
        if (!hitSet.insert(packKey(key)).second)
            continue;
        hits.push_back(packKey(key));
        if (tree.computeRayKeys(origin, tree.keyToCoord(key), ray))
            for (const auto& k : ray)
                freeSet.insert(packKey(k));
    }
    std::vector<uint64_t> misses;
    misses.reserve(freeSet.size());
    for (const uint64_t k : freeSet)
        if (hitSet.count(k) == 0)
            misses.push_back(k);
    std::sort(misses.begin(), misses.end());
    std::sort(hits.begin(), hits.end());
    for (const uint64_t k : misses)
        tree.updateNode(unpackKey(k), false);
    for (const uint64_t k : hits)
        tree.updateNode(unpackKey(k), true);

    // Colour (running mean) and class evidence, summed per voxel for this frame first.
    const int n = insertionOptions.label_count;
    std::map<uint64_t, std::vector<float>> evidence;
    for (const auto& p : points)
    {
        const octomap::OcTreeKey key =
            tree.coordToKey(p.position.x(), p.position.y(), p.position.z());
        tree.integrateNodeColor(key, p.r, p.g, p.b);
        if (p.label >= n)
            continue;
        // Likelihood of the pixel's evidence: its confidence to its label, the rest shared.
        const float c = std::clamp(p.confidence, 1.0f / static_cast<float>(n) + 1e-4f, 0.999f);
        const float rest = std::log((1.0f - c) / static_cast<float>(std::max(1, n - 1)));
        auto& e = evidence[packKey(key)];
        if (e.empty())
            e.assign(static_cast<size_t>(n), 0.0f);
        for (int k = 0; k < n; k++)
            e[static_cast<size_t>(k)] += k == p.label ? std::log(c) : rest;
    }
    // Bayesian update: log P(class | all) = log P(class | before) + log L(this frame), then
    // normalised (log-sum-exp) and floored.
    const float floor = static_cast<float>(insertionOptions.label_log_floor);
    for (auto& [key, e] : evidence)
    {
        auto& lp = impl_->classes[key];
        if (lp.empty())
            lp.assign(static_cast<size_t>(n), -std::log(static_cast<float>(n)));
        float top = -1e30f;
        for (int k = 0; k < n; k++)
        {
            lp[static_cast<size_t>(k)] += e[static_cast<size_t>(k)];
            top = std::max(top, lp[static_cast<size_t>(k)]);
        }
        double sum = 0.0;
        for (const float v : lp)
            sum += std::exp(static_cast<double>(v - top));
        const auto norm = static_cast<float>(top + std::log(sum));
        for (float& v : lp)
            v = std::max(v - norm, floor);
    }
}

bool CSemanticOctoMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const auto* o = dynamic_cast<const CObservationSemanticRGBD*>(&obs);
    if (!o)
        return false;
    const mrpt::poses::CPose3D T_world_cam = o->cameraPose(robotPose);
    const auto points = o->staticPoints(T_world_cam, insertionOptions.projection);
    insertPoints(points, Eigen::Vector3f(static_cast<float>(T_world_cam.x()),
                                         static_cast<float>(T_world_cam.y()),
                                         static_cast<float>(T_world_cam.z())));
    return true;
}

// ---- queries ----

namespace
{
void fillVoxel(const octomap::ColorOcTree& tree, const octomap::ColorOcTreeNode& node,
               const octomap::point3d& centre, const std::vector<float>* lp,
               CSemanticOctoMap::Voxel& v)
{
    v.centre = {centre.x(), centre.y(), centre.z()};
    const auto c = node.getColor();
    v.r = c.r;
    v.g = c.g;
    v.b = c.b;
    v.occupancy = static_cast<float>(node.getOccupancy());
    (void)tree;
    if (lp && !lp->empty())
    {
        const auto best = std::max_element(lp->begin(), lp->end());
        v.label = static_cast<int>(best - lp->begin());
        v.probability = std::exp(*best);
    }
}
}  // namespace

std::vector<CSemanticOctoMap::Voxel> CSemanticOctoMap::occupiedVoxels() const
{
    std::vector<std::pair<uint64_t, Voxel>> found;
    if (impl_->tree)
    {
        const auto& tree = *impl_->tree;
        for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
        {
            if (!tree.isNodeOccupied(*it))
                continue;
            const uint64_t key = packKey(it.getKey());
            const auto cls = impl_->classes.find(key);
            Voxel v;
            fillVoxel(tree, *it, it.getCoordinate(),
                      cls == impl_->classes.end() ? nullptr : &cls->second, v);
            found.emplace_back(key, v);
        }
    }
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Voxel> out;
    out.reserve(found.size());
    for (auto& [key, v] : found)
        out.push_back(v);
    return out;
}

bool CSemanticOctoMap::voxelAt(const Eigen::Vector3f& p, Voxel& out) const
{
    if (!impl_->tree)
        return false;
    const auto& tree = *impl_->tree;
    const auto key = tree.coordToKey(p.x(), p.y(), p.z());
    const auto* node = tree.search(key);
    if (!node)
        return false;
    const auto cls = impl_->classes.find(packKey(key));
    fillVoxel(tree, *node, tree.keyToCoord(key),
              cls == impl_->classes.end() ? nullptr : &cls->second, out);
    return true;
}

std::vector<float> CSemanticOctoMap::classLogProbabilities(const Eigen::Vector3f& p) const
{
    if (!impl_->tree)
        return {};
    const auto it = impl_->classes.find(packKey(impl_->tree->coordToKey(p.x(), p.y(), p.z())));
    return it == impl_->classes.end() ? std::vector<float>() : it->second;
}

size_t CSemanticOctoMap::memoryBytes() const
{
    size_t bytes = impl_->tree ? impl_->tree->memoryUsage() : 0;
    bytes += impl_->classes.size() *
             (sizeof(uint64_t) + sizeof(std::vector<float>) +
              static_cast<size_t>(insertionOptions.label_count) * sizeof(float) + 16);
    return bytes;
}

// ---- files ----

void CSemanticOctoMap::saveOt(const std::string& path, bool colourByClass) const
{
    auto copy = impl_->tree ? cloneTree(*impl_->tree)
                            : std::make_unique<octomap::ColorOcTree>(insertionOptions.resolution);
    if (colourByClass)
    {
        for (auto it = copy->begin_leafs(), end = copy->end_leafs(); it != end; ++it)
        {
            const auto cls = impl_->classes.find(packKey(it.getKey()));
            int label = 0;
            if (cls != impl_->classes.end())
                label = static_cast<int>(std::max_element(cls->second.begin(), cls->second.end()) -
                                         cls->second.begin());
            const cv::Vec3b c = labels_.colourOf(label);
            it->setColor(c[2], c[1], c[0]);
        }
    }
    core::writeFileAtomically(path,
                              [&](const std::string& tmp)
                              {
                                  if (!copy->write(tmp))
                                      throw std::runtime_error("cannot write " + path);
                              });
}

void CSemanticOctoMap::saveBt(const std::string& path) const
{
    auto copy = impl_->tree ? cloneTree(*impl_->tree)
                            : std::make_unique<octomap::ColorOcTree>(insertionOptions.resolution);
    // What OcTree::writeBinary writes (maximum likelihood, pruned), without its progress
    // message on stderr.
    copy->toMaxLikelihood();
    copy->prune();
    core::writeFileAtomically(
        path,
        [&](const std::string& tmp)
        {
            std::ofstream f(tmp, std::ios::binary);
            f << "# Octomap OcTree binary file\n"
              << "# (feel free to add / change comments, but leave the first line as it is!)\n#\n"
              << "id " << copy->getTreeType() << "\n"
              << "size " << copy->size() << "\n"
              << "res " << copy->getResolution() << "\n"
              << "data\n";
            if (copy->getRoot())
                copy->writeBinaryNode(f, copy->getRoot());
            f.flush();
            if (!f)
                throw std::runtime_error("cannot write " + path);
        });
}

void CSemanticOctoMap::loadOt(const std::string& path)
{
    std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read(path));
    if (!dynamic_cast<octomap::ColorOcTree*>(read.get()))
        throw core::InputError("'" + path + "' is not a ColorOcTree .ot file");
    impl_->tree.reset(static_cast<octomap::ColorOcTree*>(read.release()));
    impl_->classes.clear();
    insertionOptions.resolution = impl_->tree->getResolution();
}

void CSemanticOctoMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
    saveOt(prefix + ".ot", renderOptions.colour_by_class);
    saveBt(prefix + ".bt");
}

// ---- rendering, text ----

void CSemanticOctoMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const
{
    auto cloud = mrpt::opengl::CPointCloudColoured::Create();
    cloud->setPointSize(static_cast<float>(renderOptions.point_size));
    for (const auto& v : occupiedVoxels())
    {
        cv::Vec3b bgr(v.b, v.g, v.r);
        if (renderOptions.colour_by_class)
            bgr = labels_.colourOf(v.label == core::LabelSet::kVoid ? 0 : v.label);
        cloud->push_back(v.centre.x(), v.centre.y(), v.centre.z(), bgr[2] / 255.0f, bgr[1] / 255.0f,
                         bgr[0] / 255.0f);
    }
    o.insert(cloud);
}

std::string CSemanticOctoMap::asString() const
{
    return mrpt::format("CSemanticOctoMap: %zu nodes of %.3f m, %zu labelled voxels",
                        impl_->tree ? impl_->tree->size() : size_t{0}, insertionOptions.resolution,
                        impl_->classes.size());
}

// ---- serialization ----

uint8_t CSemanticOctoMap::serializeGetVersion() const
{
    return 0;
}

void CSemanticOctoMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    const auto& o = insertionOptions;
    out << o.resolution << o.projection.min_depth << o.projection.max_depth
        << static_cast<int32_t>(o.projection.stride) << o.prob_hit << o.prob_miss << o.clamping_min
        << o.clamping_max << static_cast<int32_t>(o.label_count) << o.label_log_floor
        << renderOptions.colour_by_class << renderOptions.point_size;
    std::ostringstream tree;
    if (impl_->tree)
        impl_->tree->write(tree);
    out << tree.str();
    std::vector<uint64_t> keys;
    keys.reserve(impl_->classes.size());
    for (const auto& [key, lp] : impl_->classes)
        keys.push_back(key);
    std::sort(keys.begin(), keys.end());
    out << static_cast<uint64_t>(keys.size());
    for (const uint64_t key : keys)
    {
        out << key;
        for (const float v : impl_->classes.at(key))
            out << v;
    }
}

void CSemanticOctoMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version != 0)
        MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    auto& o = insertionOptions;
    int32_t stride = 1, labels = 21;
    in >> o.resolution >> o.projection.min_depth >> o.projection.max_depth >> stride >>
        o.prob_hit >> o.prob_miss >> o.clamping_min >> o.clamping_max >> labels >>
        o.label_log_floor >> renderOptions.colour_by_class >> renderOptions.point_size;
    o.projection.stride = stride;
    o.label_count = labels;
    std::string tree;
    in >> tree;
    internal_clear();
    if (!tree.empty())
    {
        std::istringstream ss(tree);
        std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read(ss));
        if (!dynamic_cast<octomap::ColorOcTree*>(read.get()))
            throw std::runtime_error("CSemanticOctoMap: corrupt octree in the archive");
        impl_->tree.reset(static_cast<octomap::ColorOcTree*>(read.release()));
    }
    uint64_t n = 0;
    in >> n;
    for (uint64_t i = 0; i < n; i++)
    {
        uint64_t key = 0;
        in >> key;
        std::vector<float> lp(static_cast<size_t>(labels));
        for (float& v : lp)
            in >> v;
        impl_->classes[key] = std::move(lp);
    }
}
}  // namespace smap::maps
