// OctoMap occupancy with free-space carving (rays from the camera to every static point clear
// what they cross, so a person who walked away is erased), RGB colour, and a per-voxel class
// distribution fused over observations by a Bayesian log-probability update. A real MRPT
// metric map ("semanticOctoMap" in CMultiMetricMap configurations); OctoMap stays in the .cpp.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "smap/core/LabelSet.h"
#include "smap/maps/BackProjector.h"
#include "smap/maps/MapRenderOptions.h"

namespace smap::maps
{
class CSemanticOctoMap : public mrpt::maps::CMetricMap
{
    DEFINE_SERIALIZABLE(CSemanticOctoMap, smap::maps)

public:
    /// Section "<map>_insertOpts" in CMultiMetricMap configurations.
    struct TInsertionOptions : public mrpt::config::CLoadableOptions
    {
        double resolution = 0.05;             ///< m, voxel edge (fixed once the map holds data)
        BackProjectionParameters projection;  ///< pixels that become rays (stride 2 here)
        /// OctoMap's sensor model: log-odds update of a hit / a miss, and the clamping bounds.
        double prob_hit = 0.7;
        double prob_miss = 0.4;
        double clamping_min = 0.12;
        double clamping_max = 0.97;
        /// Classes of the label set (the distribution's size): PASCAL VOC 21. setLabels()
        /// sets it from the label set; a stand-alone map reads it from its configuration.
        int label_count = 21;
        /// Class log-probabilities are kept above this, so a voxel can change its mind after
        /// many views (as occupancy clamping does).
        double label_log_floor = -8.0;

        /// Whether the configuration holds the keys only a stand-alone map needs (MRPT's map
        /// factory, insertObservation): `stride` of its own back-projection and `label_count`.
        /// False where the owner sets them (semantic-mapper feeds the map points, not
        /// observations, and takes the class count from its label set).
        bool standalone_keys = true;

        TInsertionOptions() { projection.stride = 2; }
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };
    /// Section "<map>_renderOpts".
    using TRenderOptions = MapRenderOptions;

    struct Voxel
    {
        Eigen::Vector3f centre;
        uint8_t r = 0, g = 0, b = 0;
        int label = 255;           ///< most probable class (255: never labelled)
        float probability = 0.0f;  ///< its fused probability
        float occupancy = 0.0f;    ///< OctoMap occupancy probability
    };

    TInsertionOptions insertionOptions;
    TRenderOptions renderOptions;

    CSemanticOctoMap();
    ~CSemanticOctoMap() override;
    CSemanticOctoMap(const CSemanticOctoMap& other);
    CSemanticOctoMap& operator=(const CSemanticOctoMap& other);

    /// The classes the map colours by and holds distributions for: label_count becomes the
    /// set's size. Not serialized (the map stores class ids); PASCAL VOC until set.
    void setLabels(const core::LabelSet& labels);
    const core::LabelSet& labels() const { return labels_; }

    /// Rays from `sensorOrigin` to each point: voxels crossed become freer, the end voxel more
    /// occupied and takes the point's colour and class evidence.
    void insertPoints(const std::vector<SemanticPoint>& points,
                      const Eigen::Vector3f& sensorOrigin);

    /// Occupied leaf voxels (occupancy above 0.5), in a deterministic order.
    std::vector<Voxel> occupiedVoxels() const;
    /// The voxel containing a point, when the tree knows it.
    bool voxelAt(const Eigen::Vector3f& p, Voxel& out) const;
    /// Class log-probabilities of the voxel containing p (empty when never labelled).
    std::vector<float> classLogProbabilities(const Eigen::Vector3f& p) const;

    /// OctoMap files for octovis: .ot (ColorOcTree; colours by class or by RGB) and .bt
    /// (occupancy only). Written atomically; throw std::runtime_error naming the file.
    void saveOt(const std::string& path, bool colourByClass) const;
    void saveBt(const std::string& path) const;
    /// Reads an .ot written by saveOt (occupancy and colours; classes are not in .ot files).
    /// Throws core::InputError naming the file.
    void loadOt(const std::string& path);

    bool isEmpty() const override;
    /// Writes `<prefix>.ot` (coloured as renderOptions says) and `<prefix>.bt`.
    void saveMetricMapRepresentationToFile(const std::string& prefix) const override;
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const override;
    std::string asString() const override;
    /// Approximate memory use of the tree and the class distributions, bytes.
    size_t memoryBytes() const;

    MAP_DEFINITION_START(CSemanticOctoMap)
    TInsertionOptions insertionOpts;
    TRenderOptions renderOpts;
    MAP_DEFINITION_END(CSemanticOctoMap)

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    core::LabelSet labels_ = core::LabelSet::pascalVoc();

    void internal_clear() override;
    bool internal_insertObservation(
        const mrpt::obs::CObservation& obs,
        const std::optional<const mrpt::poses::CPose3D>& robotPose) override;
    double internal_computeObservationLikelihood(const mrpt::obs::CObservation&,
                                                 const mrpt::poses::CPose3D&) const override
    {
        return 0.0;
    }
    bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation&) const override
    {
        return false;
    }
    /// Creates the tree when absent, with the current options.
    void ensureTree();
};
}  // namespace smap::maps
