#include "smap/io/RawlogSource.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <deque>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "smap/core/InputError.h"
#include "smap/io/DepthRegistration.h"
#include "smap/io/RangeImageFile.h"
#include "smap/io/TumSource.h"

namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

namespace smap::io
{
namespace
{
/// Pose of an optical (x right, y down, z forward) camera in MRPT's sensor frame (x forward,
/// y left, z up): what relativePoseIntensityWRTDepth is when both cameras coincide.
mrpt::poses::CPose3D opticalInSensorFrame()
{
    return mrpt::poses::CPose3D(0, 0, 0, mrpt::DEG2RAD(-90.0), 0, mrpt::DEG2RAD(-90.0));
}

/// The root cause in an MRPT exception text: its last "Message:" line (MRPT nests the original
/// exception last, each with a call-stack dump), or the first line of any other text.
std::string innermostMrptMessage(const std::string& what)
{
    const std::string key = "Message:";
    const size_t at = what.rfind(key);
    const size_t from = at == std::string::npos ? 0 : at + key.size();
    std::string line = what.substr(from, what.find('\n', from) - from);
    const size_t first = line.find_first_not_of(' ');
    return first == std::string::npos ? what : line.substr(first);
}

bool sameIntrinsics(const core::PinholeCamera& a, const core::PinholeCamera& b)
{
    const double tol = 1e-9;
    bool same = a.width == b.width && a.height == b.height && std::abs(a.fx - b.fx) < tol &&
                std::abs(a.fy - b.fy) < tol && std::abs(a.cx - b.cx) < tol &&
                std::abs(a.cy - b.cy) < tol;
    for (size_t i = 0; i < 5; i++)
        same = same && std::abs(a.distortion[i] - b.distortion[i]) < tol;
    return same;
}

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = p.getRotationMatrix().asEigen();
    T.translation() = Eigen::Vector3d(p.x(), p.y(), p.z());
    return T;
}
}  // namespace

struct RawlogSource::Impl
{
    std::string path;
    std::string imagesDir;
    FrameSourceParameters params;
    mrpt::io::CFileGZInputStream stream;
    std::optional<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream>> archive;
    std::deque<CObservation3DRangeScan::Ptr> pending;
    std::map<std::string, size_t> classCounts;
    size_t entries = 0;
    size_t frames = 0;
    size_t rgbdWithoutImages = 0;
    size_t rgbdOtherLabel = 0;
    /// The sensor read: [rawlog] sensor_label, else the label of the first usable RGB-D
    /// observation (two cameras interleaved would be one camera jumping between two places).
    std::optional<std::string> label;
    bool ended = false;
    bool warnedDepthSize = false;
    bool warnedColourSize = false;

    // Caches keyed by the cameras and relative pose they were built for.
    struct RegistrationCache
    {
        core::PinholeCamera depthCam, colourCam;
        mrpt::poses::CPose3D T_colour_depth;
        std::unique_ptr<DepthRegistration> registration;
    };
    std::optional<RegistrationCache> registrationCache;
    std::optional<std::pair<core::PinholeCamera, std::vector<float>>> rangeToDepthCache;

    std::string resolve(const std::string& file) const
    {
        const fs::path p(file);
        return p.is_absolute() ? file : (fs::path(imagesDir) / p).string();
    }

    /// Reads entries until an RGB-D observation is queued; false at end of file.
    bool fill(COutputLogger& log);
    core::RgbdFrame convert(const CObservation3DRangeScan& obs, COutputLogger& log);
    const std::vector<float>& rangeToDepthFactors(const core::PinholeCamera& depthCam);
};

bool RawlogSource::Impl::fill(COutputLogger& log)
{
    while (pending.empty())
    {
        mrpt::serialization::CSerializable::Ptr obj;
        try
        {
            obj = archive->ReadObject();
        }
        catch (const mrpt::serialization::CExceptionEOF&)
        {
            return false;
        }
        catch (const std::exception& e)
        {
            // MRPT 2.5 reports a clean end of file as a plain exception: accept it only when
            // the stream really is at its end, so a truncated entry stays an error.
            if (stream.checkEOF() &&
                std::string(e.what()).find("Cannot read object due to EOF") != std::string::npos)
                return false;
            if (entries == 0)
                throw core::InputError(mrpt::format(
                    "'%s' is not an MRPT rawlog: its first entry cannot be read (%s); a TUM RGB-D "
                    "folder is given as the folder itself",
                    path.c_str(), innermostMrptMessage(e.what()).c_str()));
            throw core::InputError(
                mrpt::format("rawlog '%s': cannot read entry %zu (corrupt or truncated file): %s",
                             path.c_str(), entries + 1, innermostMrptMessage(e.what()).c_str()));
        }
        entries++;
        if (!obj)
            continue;
        std::vector<mrpt::obs::CObservation::Ptr> observations;
        if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
        {
            classCounts[obj->GetRuntimeClass()->className]++;
            for (const auto& o : *sf)
                observations.push_back(o);
        }
        else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
        {
            observations.push_back(o);
        }
        else
        {
            classCounts[obj->GetRuntimeClass()->className]++;
        }
        for (const auto& o : observations)
        {
            if (!o)
                continue;
            classCounts[o->GetRuntimeClass()->className]++;
            auto scan = std::dynamic_pointer_cast<CObservation3DRangeScan>(o);
            if (!scan)
                continue;
            if (label && scan->sensorLabel != *label)
            {
                if (++rgbdOtherLabel == 1 && params.rawlog_sensor_label.empty())
                {
                    log.logFmt(mrpt::system::LVL_WARN,
                               "rawlog '%s' entry %zu: RGB-D observations from another sensor "
                               "('%s'); reading only '%s', the first one seen (choose with "
                               "[rawlog] sensor_label)",
                               path.c_str(), entries, scan->sensorLabel.c_str(), label->c_str());
                }
                continue;
            }
            if (!scan->hasRangeImage || !scan->hasIntensityImage)
            {
                rgbdWithoutImages++;
                if (rgbdWithoutImages == 1)
                {
                    log.logFmt(
                        mrpt::system::LVL_WARN,
                        "rawlog '%s' entry %zu: CObservation3DRangeScan '%s' lacks a range or "
                        "intensity image; skipped (reported once)",
                        path.c_str(), entries, scan->sensorLabel.c_str());
                }
                continue;
            }
            if (!label)
                label = scan->sensorLabel;
            pending.push_back(scan);
        }
    }
    return true;
}

const std::vector<float>& RawlogSource::Impl::rangeToDepthFactors(
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

core::RgbdFrame RawlogSource::Impl::convert(const CObservation3DRangeScan& obs, COutputLogger& log)
{
    core::RgbdFrame f;
    f.index = frames;
    f.timestamp = mrpt::Clock::toDouble(obs.timestamp);

    // Colour.
    if (obs.intensityImage.isExternallyStored())
    {
        const std::string file = resolve(obs.intensityImage.getExternalStorageFile());
        f.colour = cv::imread(file, cv::IMREAD_COLOR);
        if (f.colour.empty())
            throw core::InputError(mrpt::format(
                "rawlog '%s': cannot read external colour image '%s'", path.c_str(), file.c_str()));
        f.name = fs::path(file).stem().string();
    }
    else
    {
        const cv::Mat& img = obs.intensityImage.asCvMatRef();
        if (img.channels() == 1)
            cv::cvtColor(img, f.colour, cv::COLOR_GRAY2BGR);
        else if (img.channels() == 3)
            f.colour = img.clone();
        else if (img.channels() == 4)
            cv::cvtColor(img, f.colour, cv::COLOR_BGRA2BGR);
        if (f.colour.empty() || f.colour.depth() != CV_8U)
            throw core::InputError(mrpt::format(
                "rawlog '%s' entry %zu: unsupported intensity image", path.c_str(), entries));
        f.name = mrpt::format("frame%06zu", frames);
    }

    // Range image, as raw uint16 on the depth camera's grid.
    cv::Mat raw;
    if (obs.rangeImage_isExternallyStored())
    {
        raw = readExternalRangeImage(resolve(obs.rangeImage_getExternalStorageFile("")));
    }
    else
    {
        raw.create(obs.rangeImage.rows(), obs.rangeImage.cols(), CV_16UC1);
        for (int r = 0; r < raw.rows; r++)
        {
            auto* dst = raw.ptr<uint16_t>(r);
            for (int c = 0; c < raw.cols; c++)
                dst[c] = obs.rangeImage(r, c);
        }
    }

    core::PinholeCamera depthCam = core::PinholeCamera::fromMrpt(obs.cameraParams);
    core::PinholeCamera colourCam = core::PinholeCamera::fromMrpt(obs.cameraParamsIntensity);
    const bool posesCoincide =
        obs.relativePoseIntensityWRTDepth.distanceEuclidean6D(opticalInSensorFrame()) < 1e-6;
    if (params.camera)
    {
        colourCam = *params.camera;
        if (posesCoincide)
            depthCam = colourCam;
    }
    if (depthCam.width != raw.cols || depthCam.height != raw.rows)
    {
        if (!warnedDepthSize)
        {
            log.logFmt(
                mrpt::system::LVL_WARN,
                "rawlog '%s': depth camera says %dx%d, range image is %dx%d; using the image size",
                path.c_str(), depthCam.width, depthCam.height, raw.cols, raw.rows);
            warnedDepthSize = true;
        }
        depthCam.width = raw.cols;
        depthCam.height = raw.rows;
    }
    if (colourCam.width != f.colour.cols || colourCam.height != f.colour.rows)
    {
        if (params.camera)
            throw core::InputError(mrpt::format(
                "[camera] says %dx%d but rawlog '%s' has %dx%d colour images", colourCam.width,
                colourCam.height, path.c_str(), f.colour.cols, f.colour.rows));
        if (!warnedColourSize)
        {
            log.logFmt(
                mrpt::system::LVL_WARN,
                "rawlog '%s': colour camera says %dx%d, image is %dx%d; using the image size",
                path.c_str(), colourCam.width, colourCam.height, f.colour.cols, f.colour.rows);
            warnedColourSize = true;
        }
        colourCam.width = f.colour.cols;
        colourCam.height = f.colour.rows;
    }
    if (!depthCam.isValid() || !colourCam.isValid())
        throw core::InputError(mrpt::format(
            "rawlog '%s' entry %zu: invalid intrinsics (depth %s, colour %s); give a [camera] "
            "section",
            path.c_str(), entries, depthCam.toString().c_str(), colourCam.toString().c_str()));

    cv::Mat depth;
    rawDepthToMetres(raw, obs.rangeUnits, depth);
    if (!obs.range_is_depth)
    {
        // Ranges are distances along each pixel's ray: z = range / |(x/z, y/z, 1)|.
        const auto& k = rangeToDepthFactors(depthCam);
        auto* d = depth.ptr<float>();
        for (size_t i = 0; i < depth.total(); i++)
            d[i] *= k[i];
    }

    if (posesCoincide && sameIntrinsics(depthCam, colourCam))
    {
        f.depth = depth;
    }
    else
    {
        const mrpt::poses::CPose3D T_colour_depth =
            (-obs.relativePoseIntensityWRTDepth) + opticalInSensorFrame();
        if (!registrationCache || !sameIntrinsics(registrationCache->depthCam, depthCam) ||
            !sameIntrinsics(registrationCache->colourCam, colourCam) ||
            registrationCache->T_colour_depth.distanceEuclidean6D(T_colour_depth) > 1e-12)
        {
            registrationCache.emplace(
                RegistrationCache{depthCam, colourCam, T_colour_depth,
                                  std::make_unique<DepthRegistration>(depthCam, colourCam,
                                                                      toIsometry(T_colour_depth))});
        }
        f.depth = registrationCache->registration->registerDepth(depth);
    }
    f.camera = colourCam;
    return f;
}

RawlogSource::RawlogSource(const std::string& path, const FrameSourceParameters& params)
    : FrameSource("RawlogSource"), impl_(std::make_unique<Impl>())
{
    impl_->path = path;
    impl_->params = params;
    if (!params.rawlog_sensor_label.empty())
        impl_->label = params.rawlog_sensor_label;
    const fs::path p(path);
    // Same search order as MRPT's CRawlog::detectImagesDirectory (RawLogViewer, rawlog-edit).
    impl_->imagesDir = (p.parent_path() / "Images").string();
    for (const char* suffix : {"_Images", "_images", "_IMAGES"})
    {
        const fs::path candidate = p.parent_path() / (p.stem().string() + suffix);
        if (fs::is_directory(candidate))
        {
            impl_->imagesDir = candidate.string();
            break;
        }
    }
    if (!fs::is_regular_file(path) || !impl_->stream.open(path))
        throw core::InputError(mrpt::format("cannot open rawlog '%s'", path.c_str()));
    impl_->archive.emplace(impl_->stream);
}

RawlogSource::~RawlogSource() = default;

std::optional<core::RgbdFrame> RawlogSource::next()
{
    if (impl_->ended)
        return std::nullopt;
    if (!impl_->fill(*this))
    {
        impl_->ended = true;
        if (impl_->frames == 0)
        {
            std::string found;
            for (const auto& [name, n] : impl_->classCounts)
                found += mrpt::format("%s%s x%zu", found.empty() ? "" : ", ", name.c_str(), n);
            std::string why;
            if (impl_->rgbdOtherLabel)
                why +=
                    mrpt::format("; %zu had a sensor label other than '%s'", impl_->rgbdOtherLabel,
                                 impl_->params.rawlog_sensor_label.c_str());
            if (impl_->rgbdWithoutImages)
                why += mrpt::format("; %zu lacked range or intensity images",
                                    impl_->rgbdWithoutImages);
            throw core::InputError(mrpt::format(
                "rawlog '%s' holds no usable RGB-D observation (mrpt::obs::CObservation3DRangeScan "
                "with range and intensity images); it contains: %s%s",
                impl_->path.c_str(), found.empty() ? "nothing" : found.c_str(), why.c_str()));
        }
        return std::nullopt;
    }
    auto obs = impl_->pending.front();
    impl_->pending.pop_front();
    auto frame = impl_->convert(*obs, *this);
    impl_->frames++;
    return frame;
}

std::string RawlogSource::description() const
{
    return mrpt::format("rawlog '%s'", impl_->path.c_str());
}

std::string RawlogSource::groundTruthPath() const
{
    const fs::path p(impl_->path);
    const fs::path gt = p.parent_path() / (p.stem().string() + "_groundtruth.txt");
    return fs::exists(gt) ? gt.string() : std::string();
}

const std::string& RawlogSource::imagesDirectory() const
{
    return impl_->imagesDir;
}
const std::map<std::string, size_t>& RawlogSource::classCounts() const
{
    return impl_->classCounts;
}
}  // namespace smap::io
