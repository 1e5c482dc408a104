#include "smap/io/TumSource.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "smap/core/InputError.h"
#include "smap/core/TimestampAssociation.h"
#include "smap/io/ImageFile.h"

namespace fs = std::filesystem;

namespace smap::io
{
void rawDepthToMetres(const cv::Mat& raw16, float unitsPerRaw, cv::Mat& depthMetres)
{
    depthMetres.create(raw16.size(), CV_32FC1);
    for (int r = 0; r < raw16.rows; r++)
    {
        const auto* src = raw16.ptr<uint16_t>(r);
        auto* dst = depthMetres.ptr<float>(r);
        for (int c = 0; c < raw16.cols; c++)
            dst[c] =
                src[c] == kRawDepthInvalidHigh ? 0.0F : static_cast<float>(src[c]) * unitsPerRaw;
    }
}

std::optional<std::string> implausibleDepthScale(const cv::Mat& depthMetres, double depthFactor)
{
    CV_Assert(depthMetres.type() == CV_32FC1);
    std::vector<float> valid;
    valid.reserve(depthMetres.total());
    for (int r = 0; r < depthMetres.rows; r++)
    {
        const auto* d = depthMetres.ptr<float>(r);
        for (int c = 0; c < depthMetres.cols; c++)
            if (d[c] > 0.0F && std::isfinite(d[c]))
                valid.push_back(d[c]);
    }
    if (valid.empty() || 10 * valid.size() < depthMetres.total())
        return std::nullopt;
    const auto p95 = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() * 95 / 100);
    std::nth_element(valid.begin(), p95, valid.end());
    constexpr float kNearest = 1.2F;    // m: a room-scale view reaches further
    constexpr float kFarthest = 10.0F;  // m: beyond what RGB-D sensors measure indoors
    const float far = *p95;
    if (far >= kNearest && far <= kFarthest)
        return std::nullopt;
    const bool tooNear = far < kNearest;
    // The two common mix-ups get a concrete value; anything else the raw unit to check.
    const char* hint = "; check [tum] depth_factor (raw depth units per metre)";
    if (tooNear && depthFactor == 5000.0)
    {
        hint =
            "; if the PNGs hold millimetres (7-Scenes, most RealSense / Azure Kinect "
            "recordings), set [tum] depth_factor = 1000";
    }
    else if (!tooNear && depthFactor == 1000.0)
    {
        hint = "; TUM RGB-D's PNGs hold 5000 units per metre: set [tum] depth_factor = 5000";
    }
    return mrpt::format(
        "95th percentile of the valid depth %.2f m at [tum] depth_factor = %g (%s): the depth "
        "unit looks wrong%s",
        static_cast<double>(far), depthFactor,
        tooNear ? "a whole view this close is unusual" : "further than RGB-D sensors measure",
        hint);
}

namespace
{
/// "depth/1.png" -> "depth"; "" for a bare file name.
std::string firstComponent(const std::string& relative)
{
    const fs::path p(relative);
    return p.has_parent_path() ? p.begin()->string() : std::string();
}
}  // namespace

TumSource::TumSource(const std::string& folder, const FrameSourceParameters& params)
    : FrameSource("TumSource"), folder_(folder), params_(params)
{
    const fs::path assocPath = fs::path(folder) / "associations.txt";
    if (params.tum_use_associations && fs::exists(assocPath))
        readAssociations(assocPath.string());
    else
        associateLists();
    if (params.camera)
    {
        camera_ = *params.camera;
    }
    else
    {
        camera_ = defaultKinectCamera();
        MRPT_LOG_WARN_STREAM("No [camera] configured for TUM folder '"
                             << folder << "': using the default Kinect intrinsics "
                             << camera_.toString()
                             << ". Pass a preset (config/tum_fr1.ini, tum_fr2.ini, tum_fr3.ini, "
                                "7scenes.ini, bonn.ini).");
    }
    depthCamera_ = camera_;
    if (params.depth_camera)
    {
        if (!params.camera)
            throw core::InputError(mrpt::format(
                "TUM folder '%s': [depth_camera] needs a [camera] section too (the colour camera "
                "its depth is registered to)",
                folder.c_str()));
        depthCamera_ = *params.depth_camera;
    }
}

void TumSource::warnBadLines(const std::vector<std::string>& badLines)
{
    badListLines_ += badLines.size();
    constexpr size_t kEach = 20;
    for (size_t k = 0; k < badLines.size() && k < kEach; k++)
        MRPT_LOG_WARN_STREAM(badLines[k] << " (line skipped)");
    if (badLines.size() > kEach)
        MRPT_LOG_WARN_FMT("... and %zu more malformed list lines skipped", badLines.size() - kEach);
}

void TumSource::readAssociations(const std::string& assocPath)
{
    std::vector<std::string> badLines;
    entries_ = readTumAssociations(assocPath, &badLines);
    warnBadLines(badLines);
    if (entries_.empty())
    {
        throw core::InputError(mrpt::format(
            "'%s' lists no frames (no 'rgb_timestamp rgb_file depth_timestamp depth_file' "
            "line%s): fill it, or remove it to associate rgb.txt and depth.txt",
            assocPath.c_str(),
            badLines.empty() ? "" : mrpt::format("; %zu malformed", badLines.size()).c_str()));
    }
    // associate.py run as "depth.txt rgb.txt" writes depth first: recognised by the folders.
    size_t swapped = 0;
    for (auto& e : entries_)
    {
        if (firstComponent(e.rgbFile) == "depth" && firstComponent(e.depthFile) == "rgb")
        {
            std::swap(e.rgbFile, e.depthFile);
            std::swap(e.rgbTimestamp, e.depthTimestamp);
            swapped++;
        }
    }
    if (swapped > 0)
    {
        MRPT_LOG_WARN_FMT(
            "%s: %zu line(s) list depth/ before rgb/ (associate.py given depth.txt first); read "
            "as rgb, depth",
            assocPath.c_str(), swapped);
    }
    // Pairs further apart than max_dt: one warning with the count and the first line.
    size_t apart = 0;
    const TumAssociationEntry* first = nullptr;
    for (const auto& e : entries_)
    {
        if (std::abs(e.rgbTimestamp - e.depthTimestamp) >= params_.tum_max_dt)
        {
            apart++;
            if (first == nullptr)
                first = &e;
        }
    }
    if (first != nullptr)
    {
        MRPT_LOG_WARN_FMT(
            "%s: %zu pair(s) with rgb and depth timestamps further apart than max_dt %.4f s "
            "(first at line %zu: %.4f s)",
            assocPath.c_str(), apart, params_.tum_max_dt, first->line,
            std::abs(first->rgbTimestamp - first->depthTimestamp));
    }
}

void TumSource::associateLists()
{
    const fs::path dir(folder_);
    const fs::path rgbPath = dir / "rgb.txt";
    const fs::path depthPath = dir / "depth.txt";
    if (!fs::exists(rgbPath) || !fs::exists(depthPath))
    {
        throw core::InputError(
            mrpt::format("'%s' is not a TUM RGB-D folder: it needs rgb.txt and depth.txt (or "
                         "associations.txt)",
                         folder_.c_str()));
    }
    auto readList = [this](const fs::path& path)
    {
        std::vector<std::string> badLines;
        auto list = readTumList(path.string(), &badLines);
        warnBadLines(badLines);
        if (list.empty())
            throw core::InputError(mrpt::format(
                "'%s' lists no images (no 'timestamp filename' line%s)", path.c_str(),
                badLines.empty() ? "" : mrpt::format("; %zu malformed", badLines.size()).c_str()));
        return list;
    };
    const auto rgb = readList(rgbPath);
    const auto depth = readList(depthPath);
    std::vector<double> tr, td;
    for (const auto& e : rgb)
        tr.push_back(e.timestamp);
    for (const auto& e : depth)
        td.push_back(e.timestamp);
    for (const auto& m : core::associateTimestamps(tr, td, params_.tum_max_dt))
    {
        const auto& a = rgb[m.first];
        const auto& b = depth[m.second];
        entries_.push_back({a.timestamp, a.file, b.timestamp, b.file, a.line});
    }
    if (entries_.empty())
    {
        throw core::InputError(mrpt::format(
            "TUM folder '%s': no timestamp of rgb.txt (%zu images) has one in depth.txt (%zu "
            "images) within max_dt = %g s",
            folder_.c_str(), rgb.size(), depth.size(), params_.tum_max_dt));
    }
}

std::string TumSource::absolutePath(const std::string& relative) const
{
    const fs::path p(relative);
    return p.is_absolute() ? relative : (fs::path(folder_) / p).string();
}

std::string TumSource::description() const
{
    return mrpt::format("TUM folder '%s' (%zu frames)", folder_.c_str(), entries_.size());
}

std::string TumSource::groundTruthPath() const
{
    const fs::path gt = fs::path(folder_) / "groundtruth.txt";
    return fs::exists(gt) ? gt.string() : std::string();
}

cv::Mat TumSource::readRawDepth(size_t i) const
{
    const std::string path = absolutePath(entries_.at(i).depthFile);
    cv::Mat raw;
    if (const auto problem = readDepthImage(path, raw))
        throw core::InputError(mrpt::format("depth image '%s' %s", path.c_str(), problem->c_str()));
    return raw;
}

std::optional<std::string> TumSource::readDepthImage(const std::string& path, cv::Mat& raw) const
{
    auto depth =
        readImageFile(path, cv::IMREAD_UNCHANGED, {depthCamera_.width, depthCamera_.height});
    if (depth.wrongSize)
        return depth.problem +
               (params_.depth_camera
                    ? std::string(" (the [depth_camera] size)")
                    : std::string(" (the [camera] size: give the folder's camera, e.g. --config "
                                  "config/tum_fr1.ini)"));
    if (!depth.problem.empty())
        return depth.problem;
    if (depth.image.type() != CV_16UC1)
        return mrpt::format("is not a 16-bit single-channel PNG (OpenCV type %d)",
                            depth.image.type());
    raw = depth.image;
    return std::nullopt;
}

std::optional<FrameRead> TumSource::read()
{
    if (cursor_ >= entries_.size())
        return std::nullopt;
    const size_t i = cursor_++;
    const auto& e = entries_[i];
    SkippedFrame bad{i, e.rgbTimestamp, fs::path(e.rgbFile).stem().string(), {}, {}};
    auto rejected = [&](const std::string& file, const std::string& what)
    {
        bad.file = file;
        bad.reason = what;
        return skip(bad);
    };

    core::RgbdFrame f;
    const std::string rgbPath = absolutePath(e.rgbFile);
    auto colour = readImageFile(rgbPath, cv::IMREAD_COLOR, {camera_.width, camera_.height});
    if (!colour.problem.empty())
        return rejected(rgbPath, "colour image " + colour.problem);
    f.colour = colour.image;
    const std::string depthPath = absolutePath(e.depthFile);
    cv::Mat raw;
    if (const auto problem = readDepthImage(depthPath, raw))
        return rejected(depthPath, "depth image " + *problem);
    cv::Mat depth;
    rawDepthToMetres(raw, static_cast<float>(1.0 / params_.tum_depth_factor), depth);
    if (cv::countNonZero(depth) == 0)
        return rejected(depthPath, "depth image holds no valid depth (every pixel 0 or 65535)");
    checkDepthScaleOnce(depth, depthPath);
    f.depth = toColour_.onColourGrid(depth, depthCamera_, camera_, params_.T_colour_depth);
    f.camera = camera_;
    f.timestamp = e.rgbTimestamp;
    f.index = i;
    f.name = bad.name;
    return f;
}

void TumSource::checkDepthScaleOnce(const cv::Mat& depth, const std::string& depthPath)
{
    // Only the depth unit, and only once: the first frame with depth over a tenth of it.
    if (depthScaleChecked_ || cv::countNonZero(depth) * 10 < static_cast<int>(depth.total()))
        return;
    depthScaleChecked_ = true;
    if (const auto w = implausibleDepthScale(depth, params_.tum_depth_factor))
        MRPT_LOG_WARN_FMT("depth image '%s': %s", depthPath.c_str(), w->c_str());
}
}  // namespace smap::io
