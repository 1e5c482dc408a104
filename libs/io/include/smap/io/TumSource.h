// Frames from a TUM RGB-D folder: rgb.txt + depth.txt associated as TUM's associate.py does
// (or associations.txt when present and enabled), images decoded on demand.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "smap/io/DepthToColour.h"
#include "smap/io/FrameSource.h"
#include "smap/io/TumTextFormats.h"

namespace smap::io
{
class TumSource : public FrameSource
{
public:
    /// Reads the lists (not the images). A malformed list line is warned about (naming the list
    /// and line) and left out; a missing list, or one without any frame, throws
    /// core::InputError naming it.
    TumSource(const std::string& folder, const FrameSourceParameters& params);

    /// A frame whose colour or depth image is missing, empty, undecodable, of the wrong size
    /// or type, or without any valid depth is skipped (and warned about). With a
    /// [depth_camera], the depth is put on the colour camera's grid (DepthToColour).
    std::optional<FrameRead> read() override;
    std::string description() const override;
    std::optional<size_t> sizeHint() const override { return entries_.size(); }
    std::string groundTruthPath() const override;

    /// The associated (rgb, depth) pairs, in order.
    const std::vector<TumAssociationEntry>& entries() const { return entries_; }
    /// The colour camera: every frame's camera (its depth is on this grid).
    const core::PinholeCamera& camera() const { return camera_; }
    /// The camera of the depth images as stored: the colour camera unless [depth_camera] is set.
    const core::PinholeCamera& depthCamera() const { return depthCamera_; }
    /// Maps the depth camera's optical frame to the colour camera's (identity when registered).
    const Eigen::Isometry3d& T_colour_depth() const { return params_.T_colour_depth; }
    const std::string& folder() const { return folder_; }

    /// Raw 16-bit depth of entry `i` exactly as stored in its PNG (for converters); throws
    /// core::InputError naming the image when it cannot be used.
    cv::Mat readRawDepth(size_t i) const;
    std::string absolutePath(const std::string& relative) const;
    /// Malformed lines left out of the lists.
    size_t badListLines() const { return badListLines_; }

private:
    void readAssociations(const std::string& assocPath);
    void associateLists();
    void warnBadLines(const std::vector<std::string>& badLines);
    /// The 16-bit depth PNG at `path` into `raw`, or why it cannot be used.
    std::optional<std::string> readDepthImage(const std::string& path, cv::Mat& raw) const;
    void checkDepthScaleOnce(const cv::Mat& depth, const std::string& depthPath);

    std::string folder_;
    FrameSourceParameters params_;
    core::PinholeCamera camera_;
    core::PinholeCamera depthCamera_;
    DepthToColour toColour_;
    std::vector<TumAssociationEntry> entries_;
    size_t cursor_ = 0;
    size_t badListLines_ = 0;
    bool depthScaleChecked_ = false;  ///< the first frame with enough depth was checked
};

/// Raw depth values that mean "no measurement": 0, and the largest 16-bit value, which some
/// recordings (Microsoft 7-Scenes, saturated sensor drivers) write for holes. It would otherwise
/// read as 13.1 m at TUM's 5000 units per metre or 65.5 m at millimetres.
constexpr uint16_t kRawDepthInvalidHigh = 65535;

/// Depth in metres from raw units: raw * float(1 / depthFactor); 0 where the raw value is 0 or
/// kRawDepthInvalidHigh. The same float product is used for rawlogs (raw * rangeUnits), so a TUM
/// folder and its tum2rawlog conversion agree bit for bit.
void rawDepthToMetres(const cv::Mat& raw16, float unitsPerRaw, cv::Mat& depthMetres);

/// A warning when `depthMetres` (CV_32FC1, 0 = invalid), converted at `depthFactor` raw units per
/// metre, looks like the wrong unit: the 95th percentile of its valid depths under 1.2 m (the
/// whole view that close: millimetre PNGs read at TUM's 5000 shrink depth 5x) or over 10 m (TUM's
/// 5000-unit PNGs read as millimetres stretch it 5x). Empty when plausible, or when less than a
/// tenth of the pixels has depth (nothing to judge by).
std::optional<std::string> implausibleDepthScale(const cv::Mat& depthMetres, double depthFactor);
}  // namespace smap::io
