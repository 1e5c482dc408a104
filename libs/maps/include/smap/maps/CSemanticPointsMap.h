// Coloured 3D points with a class label and confidence, voxel-downsampled: a real MRPT metric
// map (CMetricMap), declared in CMultiMetricMap configurations as "semanticPointsMap", filled
// by inserting CObservationSemanticRGBD keyframes (their static pixels, back-projected).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "smap/core/LabelSet.h"
#include "smap/maps/BackProjector.h"
#include "smap/maps/MapRenderOptions.h"

namespace smap::maps
{
class CSemanticPointsMap : public mrpt::maps::CMetricMap
{
    DEFINE_SERIALIZABLE(CSemanticPointsMap, smap::maps)

public:
    /// Section "<map>_insertOpts" in CMultiMetricMap configurations.
    struct TInsertionOptions : public mrpt::config::CLoadableOptions
    {
        double voxel_size = 0.02;  ///< m: one point per voxel
        BackProjectionParameters projection;

        void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                              const std::string& section) const override;
    };
    /// Section "<map>_renderOpts".
    using TRenderOptions = MapRenderOptions;

    TInsertionOptions insertionOptions;
    TRenderOptions renderOptions;

    CSemanticPointsMap() = default;

    /// The classes the map colours by (render option colour_by_class). Not serialized (the
    /// points store class ids); PASCAL VOC until set.
    void setLabels(const core::LabelSet& labels) { labels_ = labels; }
    const core::LabelSet& labels() const { return labels_; }

    /// Adds world points: each goes to its voxel, which keeps the mean position and colour and
    /// the class whose summed confidence is highest.
    void insertPoints(const std::vector<SemanticPoint>& points);

    /// Removes every voxel whose mean position `drop` accepts; returns how many went.
    size_t removeIf(const std::function<bool(const Eigen::Vector3f& position)>& drop);

    /// Number of occupied voxels.
    size_t size() const { return voxels_.size(); }
    /// Approximate memory use (voxels and hash table), bytes.
    size_t memoryBytes() const
    {
        return voxels_.size() * (sizeof(uint64_t) + sizeof(Voxel) + 2 * sizeof(void*)) +
               voxels_.bucket_count() * sizeof(void*);
    }
    /// One point per voxel (mean position and colour; label with its share of the summed
    /// confidence as `confidence`), ordered by voxel index (deterministic).
    std::vector<SemanticPoint> points() const;

    /// Binary little-endian PLY: x y z (float), red green blue label (uchar), confidence
    /// (float). Written atomically; throws std::runtime_error naming the file.
    void savePly(const std::string& path) const;
    /// Reads a PLY written by savePly into the voxels (as if each point were inserted once).
    /// Throws core::InputError naming the file when it is not such a PLY.
    void loadPly(const std::string& path);

    bool isEmpty() const override { return voxels_.empty(); }
    /// Writes `<prefix>.ply`.
    void saveMetricMapRepresentationToFile(const std::string& prefix) const override;
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const override;
    std::string asString() const override;

    MAP_DEFINITION_START(CSemanticPointsMap)
    TInsertionOptions insertionOpts;
    TRenderOptions renderOpts;
    MAP_DEFINITION_END(CSemanticPointsMap)

private:
    struct Voxel
    {
        double sum[3] = {0.0, 0.0, 0.0};
        uint32_t rgb[3] = {0, 0, 0};
        uint32_t count = 0;
        /// Up to 4 candidate labels with their summed confidence (label 255 = free slot).
        std::array<uint8_t, 4> labels{255, 255, 255, 255};
        std::array<float, 4> scores{};
        void add(const SemanticPoint& p);
        SemanticPoint mean() const;
    };

    core::LabelSet labels_ = core::LabelSet::pascalVoc();

    void internal_clear() override { voxels_.clear(); }
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
    uint64_t keyOf(const Eigen::Vector3f& p) const;

    std::unordered_map<uint64_t, Voxel> voxels_;
};
}  // namespace smap::maps
