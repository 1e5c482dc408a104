// The paper's Algorithm 1 (docs/method.md section 4): a keyframe's pixels split into dynamic (M)
// and static (N) from its labelled image, its depth and the dynamic feature points S.
//   1. A segmented object (connected region of one class) carrying more than Num dynamic
//      points is dynamic as a whole.
//   2. Around every other dynamic point p, a pixel closer than sigma2 in the image AND closer
//      than sigma1 in depth is dynamic.
//   3. Everything else is static.
// Beyond the paper (default): every object of a movable class (the label set's dynamic prior at
// least movable_prior; person first) is dynamic as a whole, moving or not, so that a person
// who stands still never enters the static maps.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <opencv2/core/mat.hpp>
#include <set>
#include <string>
#include <vector>

#include "smap/core/LabelSet.h"
#include "smap/core/OptionFields.h"

namespace smap::mapping
{
/// [association] section. Defaults: the paper's values (and our growth of M, grow_pixels).
struct DynamicRegionParameters : public mrpt::config::CLoadableOptions
{
    int num_points = 20;           ///< Num: more than this many dynamic points -> object dynamic
    double depth_tolerance = 0.1;  ///< sigma1 (m)
    double pixel_radius = 5.0;     ///< sigma2 (px)
    /// Classes that are never "objects" in step 1 (a floor-to-ceiling background region would
    /// otherwise be removed whole); their pixels still go through step 2. Comma-separated
    /// names of the label set.
    std::string non_object_classes = "background";
    /// 8- or 4-connectivity of object regions.
    int connectivity = 8;
    /// Beyond the paper: M grows this many pixels (4-neighbour steps) into pixels whose depth
    /// is within depth_tolerance of the M pixel they touch, so a person's outline that the
    /// segmentation gave to the background goes with the person, while the depth jump to
    /// what lies behind stops the growth. 0 = the paper's M (config/modes/paper.ini).
    int grow_pixels = 16;
    /// Beyond the paper: objects of classes whose dynamic prior (config/labels/*.csv) is at
    /// least this are dynamic whatever their points say: a person standing still is still a
    /// person. Above 1 = none (the paper, config/modes/paper.ini).
    double movable_prior = 0.5;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) const override;
    /// Every key of the section (default [association]), listed once for loading and saving.
    core::OptionFields fields(const std::string& section);
};

/// A dynamic feature point of the keyframe: pixel position and depth (m; <= 0: unknown, then
/// the depth image at the rounded position is used, and without it only the image distance
/// decides).
struct DynamicPoint
{
    double u = 0.0;
    double v = 0.0;
    double depth = 0.0;
};

/// One segmented object: a connected region of one class.
struct ObjectRegion
{
    int label = 0;
    int pixels = 0;
    int dynamicPoints = 0;  ///< points of S on it
    bool dynamic = false;   ///< removed whole (step 1, or a movable class)
    bool movable = false;   ///< of a movable class (removed whole whatever its points)
};

struct DynamicRegions
{
    cv::Mat dynamicMask;  ///< CV_8UC1, 255 on M (dynamic), 0 on N (static)
    cv::Mat objectIds;    ///< CV_32SC1, index into `objects`, -1 for non-object pixels
    std::vector<ObjectRegion> objects;
    int pixelsFromObjects = 0;  ///< step 1 and movable classes
    int pixelsMovable = 0;      ///< of those, on objects of movable classes with <= Num points
    int pixelsNearPoints = 0;   ///< step 2 (not already in step 1)
    int pixelsGrown = 0;        ///< grow_pixels (not already in steps 1-2)
};

class DynamicRegionFinder
{
public:
    /// Throws core::InputError when non_object_classes names a class `labels` lacks.
    DynamicRegionFinder(const DynamicRegionParameters& params, const core::LabelSet& labels);

    /// `labels`: CV_8UC1 class ids (255 = void, never an object); `depth`: CV_32FC1 metres (0 =
    /// none), same size; `points`: S.
    DynamicRegions find(const cv::Mat& labels, const cv::Mat& depth,
                        const std::vector<DynamicPoint>& points) const;

    const DynamicRegionParameters& parameters() const { return params_; }

private:
    /// Connected regions of each class present (void and non-object classes aside).
    void findObjects(const cv::Mat& labels, DynamicRegions& r) const;
    /// Algorithm 1 step 1: an object with more than Num dynamic points is dynamic as a whole;
    /// beyond the paper, so is every object of a movable class.
    void markDynamicObjects(const std::vector<DynamicPoint>& points, DynamicRegions& r) const;
    /// Step 2: around the other points, pixels within sigma2 in the image and sigma1 in depth.
    void markAroundPoints(const std::vector<DynamicPoint>& points, const cv::Mat& depth,
                          DynamicRegions& r) const;
    DynamicRegionParameters params_;
    std::set<int> nonObject_;
    std::set<int> movable_;  ///< class ids with dynamic prior >= movable_prior
};
}  // namespace smap::mapping
