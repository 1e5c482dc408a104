// TUM RGB-D folder -> MRPT rawlog of CObservation3DRangeScan (what tum2rawlog does).
//
// The rawlog holds one bare observation per associated (rgb, depth) pair, with images stored
// externally in "<name>_Images/" (colour files copied byte for byte; depth as MRPT .bin range
// images in the source's own units, rangeUnits = 1 / depth_factor), so it stays small and opens
// in RawLogViewer. Images keep the paths the lists give them; one listed by an absolute path or
// one outside the folder ("../") goes to outside/rgb|depth/INDEX/NAME instead. Depth stays as
// recorded: cameraParams is the source's depth camera, cameraParamsIntensity its colour camera
// and relativePoseIntensityWRTDepth their extrinsic (the optical-to-sensor rotation alone when
// the folder's depth is registered; [depth_camera] otherwise), so the rawlog reads back as the
// folder does.
// groundtruth.txt, when present, is written as "<name>_groundtruth.txt" beside the rawlog, and
// any further reference beside it (groundtruth_sfm.txt) as "<name>_groundtruth_sfm.txt".
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <string>

#include "smap/io/TumSource.h"

namespace smap::io
{
class TumToRawlogConverter : public mrpt::system::COutputLogger
{
public:
    struct Result
    {
        size_t frames = 0;
        std::string rawlogPath;
        std::string imagesDirectory;
        std::string groundTruthPath;  ///< empty when the folder had no ground truth
    };

    explicit TumToRawlogConverter(std::string sensorLabel = "RGBD");

    /// Writes atomically: the rawlog and its images folder appear only when complete; an
    /// existing output of the same name is replaced. `maxFrames` = 0 converts all.
    Result convert(TumSource& source, double depthFactor, const std::string& outRawlog,
                   size_t maxFrames = 0);

private:
    /// Frames 0..n-1 into the rawlog and the images folder (temporary paths); returns n.
    size_t writeFrames(TumSource& source, double depthFactor, size_t n,
                       const std::string& rawlogPath, const std::string& imagesDir) const;
    /// The ground truth and the references beside it copied as `<stem>_<name>` into `folder`;
    /// returns the ground truth's copy (empty without one).
    static std::string copyReferences(const std::string& groundTruth, const std::string& folder,
                                      const std::string& stem);

    std::string sensorLabel_;
};
}  // namespace smap::io
