// Frames from a TUM RGB-D folder: rgb.txt + depth.txt associated as TUM's associate.py does
// (or associations.txt when present and enabled), images decoded on demand.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "smap/io/FrameSource.h"
#include "smap/io/TumTextFormats.h"

namespace smap::io
{
class TumSource : public FrameSource
{
public:
    /// Reads the lists (not the images); throws core::InputError on missing or malformed lists.
    TumSource(const std::string& folder, const FrameSourceParameters& params);

    std::optional<core::RgbdFrame> next() override;
    std::string description() const override;
    std::optional<size_t> sizeHint() const override { return entries_.size(); }
    std::string groundTruthPath() const override;

    /// The associated (rgb, depth) pairs, in order.
    const std::vector<TumAssociationEntry>& entries() const { return entries_; }
    const core::PinholeCamera& camera() const { return camera_; }
    const std::string& folder() const { return folder_; }

    /// Raw 16-bit depth of entry `i` exactly as stored in its PNG (for converters).
    cv::Mat readRawDepth(size_t i) const;
    std::string absolutePath(const std::string& relative) const;

private:
    std::string folder_;
    FrameSourceParameters params_;
    core::PinholeCamera camera_;
    std::vector<TumAssociationEntry> entries_;
    size_t cursor_ = 0;
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
