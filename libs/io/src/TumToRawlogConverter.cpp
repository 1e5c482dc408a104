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

    const auto& entries = source.entries();
    const size_t n = maxFrames == 0 ? entries.size() : std::min(maxFrames, entries.size());
    const auto rangeUnits = static_cast<float>(1.0 / depthFactor);
    const core::PinholeCamera& cam = source.camera();
    mrpt::system::CTicTac timer;
    double lastReport = 0.0;

    Result result;
    // The images folder is complete before the rawlog that references it appears.
    core::writeFileAtomically(
        outRawlog,
        [&](const std::string& tmpRawlog)
        {
            core::writeDirectoryAtomically(
                imagesDir.string(),
                [&](const std::string& tmpImages)
                {
                    const fs::path tmpImagesDir(tmpImages);
                    mrpt::io::CFileGZOutputStream fo;
                    // Compression level 0: a plain rawlog, fastest to write and read.
                    if (!fo.open(tmpRawlog, 0))
                        throw std::runtime_error(
                            mrpt::format("cannot create '%s'", tmpRawlog.c_str()));
                    auto arch = mrpt::serialization::archiveFrom(fo);
                    for (size_t i = 0; i < n; i++)
                    {
                        const auto& e = entries[i];
                        const fs::path rgbRel = pathInImagesDir(e.rgbFile, "rgb", i);
                        const fs::path rgbSrc = source.absolutePath(e.rgbFile);
                        if (!fs::exists(rgbSrc))
                            throw core::InputError(
                                mrpt::format("colour image '%s' does not exist", rgbSrc.c_str()));
                        if (i == 0)  // colour is copied, not decoded: its size checked once
                        {
                            const cv::Mat c = cv::imread(rgbSrc.string(), cv::IMREAD_UNCHANGED);
                            if (c.empty())
                                throw core::InputError(mrpt::format(
                                    "colour image '%s' cannot be read", rgbSrc.c_str()));
                            if (c.cols != cam.width || c.rows != cam.height)
                                throw core::InputError(mrpt::format(
                                    "colour image '%s' is %dx%d but the camera is %dx%d (give "
                                    "the folder's [camera], e.g. --config config/tum_fr1.ini)",
                                    rgbSrc.c_str(), c.cols, c.rows, cam.width, cam.height));
                        }
                        fs::create_directories((tmpImagesDir / rgbRel).parent_path());
                        fs::copy_file(rgbSrc, tmpImagesDir / rgbRel,
                                      fs::copy_options::overwrite_existing);

                        const cv::Mat raw = source.readRawDepth(i);  // of the depth camera's size
                        auto obs = mrpt::obs::CObservation3DRangeScan::Create();
                        obs->sensorLabel = sensorLabel_;
                        obs->timestamp = mrpt::Clock::fromDouble(e.rgbTimestamp);
                        obs->hasRangeImage = true;
                        obs->range_is_depth = true;
                        obs->rangeUnits = rangeUnits;
                        // MRPT marks a missing range by 0: holes written as 65535 become 0.
                        obs->rangeImage_setSize(raw.rows, raw.cols);
                        uint16_t maxRaw = 0;
                        for (int r = 0; r < raw.rows; r++)
                        {
                            const auto* src = raw.ptr<uint16_t>(r);
                            for (int c = 0; c < raw.cols; c++)
                            {
                                const uint16_t v = src[c] == kRawDepthInvalidHigh ? 0 : src[c];
                                obs->rangeImage(r, c) = v;
                                maxRaw = std::max(maxRaw, v);
                            }
                        }
                        // A Kinect-like device maximum (viewers scale depth by it), raised when the
                        // frame holds farther data so that nothing lies beyond maxRange.
                        obs->maxRange = std::max(10.0f, static_cast<float>(maxRaw) * rangeUnits);
                        const fs::path depthRel =
                            pathInImagesDir(e.depthFile, "depth", i).replace_extension(".bin");
                        fs::create_directories((tmpImagesDir / depthRel).parent_path());
                        obs->rangeImage_convertToExternalStorage(depthRel.string(),
                                                                 tmpImagesDir.string() + "/");

                        obs->hasIntensityImage = true;
                        obs->intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
                        obs->intensityImage.setExternalStorage(rgbRel.string());
                        obs->cameraParams = source.depthCamera().toMrpt();
                        obs->cameraParamsIntensity = cam.toMrpt();
                        obs->relativePoseIntensityWRTDepth =
                            relativePoseIntensityWRTDepth(source.T_colour_depth());
                        arch << *obs;
                        result.frames++;

                        if (timer.Tac() - lastReport > 2.0)
                        {
                            lastReport = timer.Tac();
                            MRPT_LOG_INFO_FMT("converted %zu / %zu frames (%.1f frames/s)", i + 1,
                                              n, (i + 1) / lastReport);
                        }
                    }
                    fo.close();
                },
                // An existing images folder is replaced only with the rawlog that uses it.
                [&](const std::string&) { return fs::is_regular_file(outRawlog); });
        });
    result.rawlogPath = outRawlog;
    result.imagesDirectory = imagesDir.string();
    if (const std::string gt = source.groundTruthPath(); !gt.empty())
    {
        // groundtruth.txt as <name>_groundtruth.txt, and any further reference beside it
        // (groundtruth_sfm.txt) as <name>_groundtruth_sfm.txt: the rawlog keeps them all.
        for (const auto& reference : referenceTrajectories(gt))
        {
            const std::string name = fs::path(reference).filename().string();
            const std::string copy = (parent / (out.stem().string() + "_" + name)).string();
            writeTumTrajectory(copy, readTumTrajectory(reference),
                               "ground truth from " + reference);
            if (reference == gt)
                result.groundTruthPath = copy;
        }
    }
    MRPT_LOG_INFO_FMT("wrote %zu frames to '%s' (images in '%s')", result.frames, outRawlog.c_str(),
                      result.imagesDirectory.c_str());
    return result;
}
}  // namespace smap::io
