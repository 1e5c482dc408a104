#include "smap/io/TumToRawlogConverter.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/CTicTac.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "SensorExtrinsics.h"
#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"
#include "smap/io/TumTextFormats.h"

namespace fs = std::filesystem;

namespace smap::io
{
TumToRawlogConverter::TumToRawlogConverter(std::string sensorLabel)
    : COutputLogger("TumToRawlogConverter"), sensorLabel_(std::move(sensorLabel))
{
}

namespace
{
/// Where a listed image goes below OUT_Images/: its path as listed (relative to the TUM folder),
/// or, for an absolute path or one leading out of the folder ("../"), which would land outside
/// OUT_Images or on the source file itself, outside/KIND/INDEX/NAME (the name, hence the
/// frame's name read back, stays the file's own).
fs::path pathInImagesDir(const std::string& listed, const char* kind, size_t index)
{
    fs::path p = fs::path(listed).lexically_normal();
    const bool leavesFolder = p.is_absolute() || p.empty() || *p.begin() == "..";
    if (!leavesFolder)
        return p;
    return fs::path("outside") / kind / std::to_string(index) / p.filename();
}

/// Colour is copied, not decoded: its size is checked once, on the first frame.
void checkColourSize(const fs::path& rgbSrc, const core::PinholeCamera& cam)
{
    const cv::Mat c = cv::imread(rgbSrc.string(), cv::IMREAD_UNCHANGED);
    if (c.empty())
        throw core::InputError(mrpt::format("colour image '%s' cannot be read", rgbSrc.c_str()));
    if (c.cols != cam.width || c.rows != cam.height)
        throw core::InputError(mrpt::format(
            "colour image '%s' is %dx%d but the camera is %dx%d (give the folder's [camera], "
            "e.g. --config config/tum_fr1.ini)",
            rgbSrc.c_str(), c.cols, c.rows, cam.width, cam.height));
}

/// The range image of raw depth (of the depth camera's size); returns the largest raw value.
uint16_t fillRangeImage(const cv::Mat& raw, mrpt::obs::CObservation3DRangeScan& obs)
{
    // MRPT marks a missing range by 0: holes written as 65535 become 0.
    obs.rangeImage_setSize(raw.rows, raw.cols);
    uint16_t maxRaw = 0;
    for (int r = 0; r < raw.rows; r++)
    {
        const auto* src = raw.ptr<uint16_t>(r);
        for (int c = 0; c < raw.cols; c++)
        {
            const uint16_t v = src[c] == kRawDepthInvalidHigh ? 0 : src[c];
            obs.rangeImage(r, c) = v;
            maxRaw = std::max(maxRaw, v);
        }
    }
    return maxRaw;
}

/// Frame i as an observation whose images live below `imagesDir` (colour copied there, depth
/// written there as an MRPT range image).
mrpt::obs::CObservation3DRangeScan::Ptr makeObservation(TumSource& source, double depthFactor,
                                                        size_t i, const fs::path& imagesDir,
                                                        const std::string& sensorLabel)
{
    const auto& e = source.entries()[i];
    const core::PinholeCamera& cam = source.camera();
    const auto rangeUnits = static_cast<float>(1.0 / depthFactor);
    const fs::path rgbRel = pathInImagesDir(e.rgbFile, "rgb", i);
    const fs::path rgbSrc = source.absolutePath(e.rgbFile);
    if (!fs::exists(rgbSrc))
        throw core::InputError(mrpt::format("colour image '%s' does not exist", rgbSrc.c_str()));
    if (i == 0)
        checkColourSize(rgbSrc, cam);
    fs::create_directories((imagesDir / rgbRel).parent_path());
    fs::copy_file(rgbSrc, imagesDir / rgbRel, fs::copy_options::overwrite_existing);

    auto obs = mrpt::obs::CObservation3DRangeScan::Create();
    obs->sensorLabel = sensorLabel;
    obs->timestamp = mrpt::Clock::fromDouble(e.rgbTimestamp);
    obs->hasRangeImage = true;
    obs->range_is_depth = true;
    obs->rangeUnits = rangeUnits;
    const uint16_t maxRaw = fillRangeImage(source.readRawDepth(i), *obs);
    // A Kinect-like device maximum (viewers scale depth by it), raised when the frame holds
    // farther data so that nothing lies beyond maxRange.
    obs->maxRange = std::max(10.0f, static_cast<float>(maxRaw) * rangeUnits);
    const fs::path depthRel = pathInImagesDir(e.depthFile, "depth", i).replace_extension(".bin");
    fs::create_directories((imagesDir / depthRel).parent_path());
    obs->rangeImage_convertToExternalStorage(depthRel.string(), imagesDir.string() + "/");

    obs->hasIntensityImage = true;
    obs->intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
    obs->intensityImage.setExternalStorage(rgbRel.string());
    obs->cameraParams = source.depthCamera().toMrpt();
    obs->cameraParamsIntensity = cam.toMrpt();
    obs->relativePoseIntensityWRTDepth = relativePoseIntensityWRTDepth(source.T_colour_depth());
    return obs;
}

}  // namespace

TumToRawlogConverter::Result TumToRawlogConverter::convert(TumSource& source, double depthFactor,
                                                           const std::string& outRawlog,
                                                           size_t maxFrames)
{
    const fs::path out(outRawlog);
    const fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    if (!fs::is_directory(parent))
        throw core::InputError(mrpt::format("output folder '%s' does not exist", parent.c_str()));
    const fs::path imagesDir = parent / (out.stem().string() + "_Images");
    const size_t n =
        maxFrames == 0 ? source.entries().size() : std::min(maxFrames, source.entries().size());

    Result result;
    // The images folder is complete before the rawlog that references it appears.
    core::writeFileAtomically(
        outRawlog,
        [&](const std::string& tmpRawlog)
        {
            core::writeDirectoryAtomically(
                imagesDir.string(),
                [&](const std::string& tmpImages)
                { result.frames = writeFrames(source, depthFactor, n, tmpRawlog, tmpImages); },
                // An existing images folder is replaced only with the rawlog that uses it.
                [&](const std::string&) { return fs::is_regular_file(outRawlog); });
        });
    result.rawlogPath = outRawlog;
    result.imagesDirectory = imagesDir.string();
    result.groundTruthPath =
        copyReferences(source.groundTruthPath(), parent.string(), out.stem().string());
    MRPT_LOG_INFO_FMT("wrote %zu frames to '%s' (images in '%s')", result.frames, outRawlog.c_str(),
                      result.imagesDirectory.c_str());
    return result;
}

size_t TumToRawlogConverter::writeFrames(TumSource& source, double depthFactor, size_t n,
                                         const std::string& rawlogPath,
                                         const std::string& imagesDir) const
{
    mrpt::io::CFileGZOutputStream fo;
    // Compression level 0: a plain rawlog, fastest to write and read.
    if (!fo.open(rawlogPath, 0))
        throw std::runtime_error(mrpt::format("cannot create '%s'", rawlogPath.c_str()));
    auto arch = mrpt::serialization::archiveFrom(fo);
    mrpt::system::CTicTac timer;
    double lastReport = 0.0;
    for (size_t i = 0; i < n; i++)
    {
        arch << *makeObservation(source, depthFactor, i, fs::path(imagesDir), sensorLabel_);
        if (timer.Tac() - lastReport > 2.0)
        {
            lastReport = timer.Tac();
            MRPT_LOG_INFO_FMT("converted %zu / %zu frames (%.1f frames/s)", i + 1, n,
                              (i + 1) / lastReport);
        }
    }
    fo.close();
    return n;
}

std::string TumToRawlogConverter::copyReferences(const std::string& groundTruth,
                                                 const std::string& folder, const std::string& stem)
{
    // groundtruth.txt as <stem>_groundtruth.txt, and any further reference beside it
    // (groundtruth_sfm.txt) as <stem>_groundtruth_sfm.txt: the rawlog keeps them all.
    std::string copied;
    if (groundTruth.empty())
        return copied;
    for (const auto& reference : referenceTrajectories(groundTruth))
    {
        const std::string name = fs::path(reference).filename().string();
        const std::string copy =
            (fs::path(folder) / std::string(stem).append("_").append(name)).string();
        writeTumTrajectory(copy, readTumTrajectory(reference),
                           std::string("ground truth from ").append(reference));
        if (reference == groundTruth)
            copied = copy;
    }
    return copied;
}
}  // namespace smap::io
