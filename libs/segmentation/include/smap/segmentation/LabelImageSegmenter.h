// Precomputed segmentations from disk: one 8-bit label image per frame (the project's class
// ids, 255 = void), or one multi-page probability image per frame, matched by the frame's name
// or by timestamp. This is how the paper fed its
// segmentation, how any external network plugs in, and how synthetic ground truth comes in.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <map>
#include <string>

#include "smap/core/OptionFields.h"
#include "smap/segmentation/Segmenter.h"

namespace smap::segmentation
{
/// [label_images] section.
struct LabelImageParameters : public mrpt::config::CLoadableOptions
{
    /// Folder of label images (PNG, CV_8UC1) or probability images (TIFF).
    std::string folder;
    /// "labels": <name>.png, 8-bit class ids. "probabilities": <name>.tiff, one page per class
    /// of the label set in id order, 8-bit (p x 255), 16-bit (p x 65535) or float; columns are
    /// renormalised.
    std::string kind = "labels";
    /// "name": FOLDER/<frame name>.png (a TUM frame's name is its colour file's stem);
    /// "timestamp": files named <seconds>.png, the nearest within max_dt of the frame's time.
    std::string match = "name";
    double max_dt = 0.02;
    /// Probability given to the image's label; the rest is shared by the other labels.
    double confidence = 0.9;
    /// Optional folder of 8-bit images of the same names: the label's probability x 255,
    /// which replaces `confidence` pixel by pixel.
    std::string confidence_folder;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [label_images]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};

class LabelImageSegmenter : public Segmenter
{
public:
    /// Throws core::InputError when the folder does not exist or holds no PNG.
    LabelImageSegmenter(const LabelImageParameters& params, core::LabelSet labels);

    /// Throws core::InputError naming the frame when no image matches it, and naming the file
    /// when it is not an 8-bit single-channel image, holds an id outside the label set (other
    /// than 255) or has another aspect ratio than the frame.
    SegmentationResult segmentNative(const core::RgbdFrame& frame) override;
    std::string description() const override;

    /// The label image file for a frame (the rule of `match`), or "" when none.
    std::string fileFor(const core::RgbdFrame& frame) const;

private:
    SegmentationResult readProbabilities(const std::string& path,
                                         const core::RgbdFrame& frame) const;

    LabelImageParameters params_;
    std::string extension_;  ///< ".png" (labels) or ".tiff" (probabilities)
    std::map<double, std::string> byTimestamp_;
};
}  // namespace smap::segmentation
