#include "smap/io/RgbdObservationConverter.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "SensorExtrinsics.h"
#include "smap/core/InputError.h"
#include "smap/io/DepthRegistration.h"
#include "smap/io/DepthToColour.h"
#include "smap/io/ImageFile.h"
#include "smap/io/RangeImageFile.h"
#include "smap/io/TumSource.h"

namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

namespace smap::io
{
struct RgbdObservationConverter::Impl
{
    FrameSourceParameters params;
    std::string imagesDir;
    DepthToColour toColour;
    // Keyed by the depth camera it was built for.
    std::optional<std::pair<core::PinholeCamera, std::vector<float>>> rangeToDepthCache;
    bool warnedDepthSize = false;
    bool warnedColourSize = false;

    /// Depth and colour cameras and T_colour_depth: the observation's, or the configuration's.
    struct Cameras
    {
        core::PinholeCamera depth, colour;
        Eigen::Isometry3d T_colour_depth;
    };

    std::string resolve(const std::string& file) const
    {
        const fs::path p(file);
        return p.is_absolute() || imagesDir.empty() ? file : (fs::path(imagesDir) / p).string();
    }
    void readColour(const CObservation3DRangeScan& obs, const std::string& where,
                    core::RgbdFrame& f) const;
    cv::Mat readRawRange(const CObservation3DRangeScan& obs) const;
    Cameras camerasOf(const CObservation3DRangeScan& obs, const cv::Mat& raw, const cv::Mat& colour,
                      const std::string& where, mrpt::system::COutputLogger& log);
    /// A camera whose size differs from its images: an error when the configuration gave it,
    /// else the image size (warned once).
    void fitToImage(core::PinholeCamera& cam, const cv::Mat& image, bool depth, bool configured,
                    const std::string& where, mrpt::system::COutputLogger& log);
    const std::vector<float>& rangeToDepthFactors(const core::PinholeCamera& depthCam);
};

RgbdObservationConverter::RgbdObservationConverter(const FrameSourceParameters& params,
                                                   std::string imagesDirectory)
    : COutputLogger("RgbdObservationConverter"), impl_(std::make_unique<Impl>())
{
    impl_->params = params;
    impl_->imagesDir = std::move(imagesDirectory);
}

RgbdObservationConverter::~RgbdObservationConverter() = default;
RgbdObservationConverter::RgbdObservationConverter(RgbdObservationConverter&&) noexcept = default;
RgbdObservationConverter& RgbdObservationConverter::operator=(RgbdObservationConverter&&) noexcept =
    default;

core::RgbdFrame RgbdObservationConverter::convert(const CObservation3DRangeScan& obs,
                                                  const std::string& where)
{
    if (!obs.hasRangeImage || !obs.hasIntensityImage)
        throw core::InputError(mrpt::format("%s: CObservation3DRangeScan '%s' lacks its %s image",
                                            where.c_str(), obs.sensorLabel.c_str(),
                                            obs.hasRangeImage ? "intensity" : "range"));
    core::RgbdFrame f;
    f.timestamp = mrpt::Clock::toDouble(obs.timestamp);
    impl_->readColour(obs, where, f);
    // Range image, as raw uint16 on the depth camera's grid.
    const cv::Mat raw = impl_->readRawRange(obs);
    const Impl::Cameras cams = impl_->camerasOf(obs, raw, f.colour, where, *this);
    cv::Mat depth;
    rawDepthToMetres(raw, obs.rangeUnits, depth);
    if (!obs.range_is_depth)
    {
        // Ranges are distances along each pixel's ray: z = range / |(x/z, y/z, 1)|.
        const auto& k = impl_->rangeToDepthFactors(cams.depth);
        auto* d = depth.ptr<float>();
        for (size_t i = 0; i < depth.total(); i++)
            d[i] *= k[i];
    }
    f.depth = impl_->toColour.onColourGrid(depth, cams.depth, cams.colour, cams.T_colour_depth);
    f.camera = cams.colour;
    if (cv::countNonZero(f.depth) == 0)
        throw core::InputError(where + ": the range image holds no valid depth (every pixel 0)");
    return f;
}

const std::vector<float>& RgbdObservationConverter::Impl::rangeToDepthFactors(
    const core::PinholeCamera& depthCam)
{
    if (!rangeToDepthCache || !sameIntrinsics(rangeToDepthCache->first, depthCam))
    {
        std::vector<float> factors;
        for (const auto& r : undistortedPixelRays(depthCam))
            factors.push_back(1.0f / std::sqrt(1.0f + r.x * r.x + r.y * r.y));
        rangeToDepthCache.emplace(depthCam, std::move(factors));
    }
    return rangeToDepthCache->second;
}

void RgbdObservationConverter::Impl::readColour(const CObservation3DRangeScan& obs,
                                                const std::string& where, core::RgbdFrame& f) const
{
    if (obs.intensityImage.isExternallyStored())
    {
        const std::string file = resolve(obs.intensityImage.getExternalStorageFile());
        auto colour = readImageFile(file, cv::IMREAD_COLOR);
        if (!colour.problem.empty())
            throw core::InputError(mrpt::format("external colour image '%s' %s", file.c_str(),
                                                colour.problem.c_str()));
        f.colour = colour.image;
        f.name = fs::path(file).stem().string();
        return;
    }
    const cv::Mat& img = obs.intensityImage.asCvMatRef();
    if (img.channels() == 1)
        cv::cvtColor(img, f.colour, cv::COLOR_GRAY2BGR);
    else if (img.channels() == 3)
        f.colour = img.clone();
    else if (img.channels() == 4)
        cv::cvtColor(img, f.colour, cv::COLOR_BGRA2BGR);
    if (f.colour.empty() || f.colour.depth() != CV_8U)
        throw core::InputError(where + ": unsupported intensity image");
}

cv::Mat RgbdObservationConverter::Impl::readRawRange(const CObservation3DRangeScan& obs) const
{
    if (obs.rangeImage_isExternallyStored())
        return readExternalRangeImage(resolve(obs.rangeImage_getExternalStorageFile("")));
    cv::Mat raw(obs.rangeImage.rows(), obs.rangeImage.cols(), CV_16UC1);
    for (int r = 0; r < raw.rows; r++)
    {
        auto* dst = raw.ptr<uint16_t>(r);
        for (int c = 0; c < raw.cols; c++)
            dst[c] = obs.rangeImage(r, c);
    }
    return raw;
}

RgbdObservationConverter::Impl::Cameras RgbdObservationConverter::Impl::camerasOf(
    const CObservation3DRangeScan& obs, const cv::Mat& raw, const cv::Mat& colour,
    const std::string& where, mrpt::system::COutputLogger& log)
{
    Cameras c{core::PinholeCamera::fromMrpt(obs.cameraParams),
              core::PinholeCamera::fromMrpt(obs.cameraParamsIntensity),
              colourFromDepth(obs.relativePoseIntensityWRTDepth)};
    if (params.camera)
    {
        c.colour = *params.camera;
        if (isIdentity(c.T_colour_depth))
            c.depth = c.colour;
    }
    if (params.depth_camera)  // the configuration knows the sensor better than the recording
    {
        c.depth = *params.depth_camera;
        c.T_colour_depth = params.T_colour_depth;
    }
    fitToImage(c.depth, raw, true, params.depth_camera.has_value(), where, log);
    fitToImage(c.colour, colour, false, params.camera.has_value(), where, log);
    if (!c.depth.isValid() || !c.colour.isValid())
        throw core::InputError(
            mrpt::format("%s: invalid intrinsics (depth %s, colour %s); give a [camera] section",
                         where.c_str(), c.depth.toString().c_str(), c.colour.toString().c_str()));
    return c;
}

void RgbdObservationConverter::Impl::fitToImage(core::PinholeCamera& cam, const cv::Mat& image,
                                                bool depth, bool configured,
                                                const std::string& where,
                                                mrpt::system::COutputLogger& log)
{
    if (cam.width == image.cols && cam.height == image.rows)
        return;
    if (configured)
        throw core::InputError(mrpt::format("[%s] says %dx%d but %s has %dx%d %s images",
                                            depth ? "depth_camera" : "camera", cam.width,
                                            cam.height, where.c_str(), image.cols, image.rows,
                                            depth ? "range" : "colour"));
    bool& warned = depth ? warnedDepthSize : warnedColourSize;
    if (!warned)
    {
        log.logFmt(mrpt::system::LVL_WARN,
                   "%s: %s camera says %dx%d, %s is %dx%d; using the image size", where.c_str(),
                   depth ? "depth" : "colour", cam.width, cam.height,
                   depth ? "range image" : "image", image.cols, image.rows);
        warned = true;
    }
    cam.width = image.cols;
    cam.height = image.rows;
}
}  // namespace smap::io
