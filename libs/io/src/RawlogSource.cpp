#include "smap/io/RawlogSource.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/aligned_allocator.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <new>
#include <optional>

#include "smap/core/InputError.h"
#include "smap/io/RgbdObservationConverter.h"

namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

namespace smap::io
{
namespace
{
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

/// The uncompressed size (mod 2^32) a gzip file's trailer states; nullopt for other files.
std::optional<uint32_t> gzipTrailerSize(const std::string& path, uint64_t fileSize)
{
    std::ifstream in(path, std::ios::binary);
    unsigned char magic[2] = {0, 0};
    constexpr uint64_t kSmallestGzip = 18;  // a 10-byte header, data, an 8-byte trailer
    if (!in.read(reinterpret_cast<char*>(magic), 2) || magic[0] != 0x1f || magic[1] != 0x8b ||
        fileSize < kSmallestGzip)
        return std::nullopt;
    unsigned char tail[4];
    in.seekg(static_cast<std::streamoff>(fileSize - 4));
    if (!in.read(reinterpret_cast<char*>(tail), 4))
        return std::nullopt;
    return static_cast<uint32_t>(tail[0] | (tail[1] << 8) | (tail[2] << 16) |
                                 (static_cast<uint32_t>(tail[3]) << 24));
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
    uint64_t fileSize = 0;
    /// For a gzip file, the size of its data modulo 2^32 as its trailer (last 4 bytes) says.
    std::optional<uint32_t> gzipDataSize;
    std::string damage;  ///< why reading stopped before the end of the file, if it did
    /// The sensor read: [rawlog] sensor_label, else the label of the first usable RGB-D
    /// observation (two cameras interleaved would be one camera jumping between two places).
    std::optional<std::string> label;
    bool ended = false;

    std::optional<RgbdObservationConverter> converter;

    /// Reads entries until an RGB-D observation is queued; false at the end of the file, or
    /// at damage (`damage` says where) after the first entry.
    bool fill(COutputLogger& log);
    /// The error for a rawlog that ended without a single usable RGB-D observation.
    std::string nothingUsable() const;
    /// At the end of the data: sets `damage` when the file is gzip and its data is shorter than
    /// its trailer says (a compressed recording cut short, even between two entries).
    void noteMissingGzipTrailer(size_t entriesRead);
    /// The next entry; null at the end of the data (`damage` says when it was not the end).
    std::optional<mrpt::serialization::CSerializable::Ptr> readEntry();
    /// Queues an RGB-D observation when it is of the sensor read and has both images.
    void queueIfUsable(const CObservation3DRangeScan::Ptr& scan, COutputLogger& log);
};

namespace
{
/// The observations of a rawlog entry (a sensory frame's, or the entry itself).
std::vector<mrpt::obs::CObservation::Ptr> observationsOf(
    const mrpt::serialization::CSerializable::Ptr& obj, std::map<std::string, size_t>& classCounts)
{
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
    return observations;
}
}  // namespace

bool RawlogSource::Impl::fill(COutputLogger& log)
{
    while (pending.empty())
    {
        const auto obj = readEntry();
        if (!obj)
            return false;
        if (!*obj)
            continue;
        for (const auto& o : observationsOf(*obj, classCounts))
        {
            if (!o)
                continue;
            classCounts[o->GetRuntimeClass()->className]++;
            if (auto scan = std::dynamic_pointer_cast<CObservation3DRangeScan>(o))
                queueIfUsable(scan, log);
        }
    }
    return true;
}

std::optional<mrpt::serialization::CSerializable::Ptr> RawlogSource::Impl::readEntry()
{
    mrpt::serialization::CSerializable::Ptr obj;
    const uint64_t entryStart = stream.getPosition();
    try
    {
        obj = archive->ReadObject();
    }
    catch (const std::exception& e)
    {
        // The end of the file between two entries is the end of the recording (MRPT 2.5
        // reports it as CExceptionEOF or as a plain exception); an end inside an entry, or
        // anything else, is damage.
        const bool atEnd =
            dynamic_cast<const mrpt::serialization::CExceptionEOF*>(&e) != nullptr ||
            std::string(e.what()).find("Cannot read object due to EOF") != std::string::npos;
        if (atEnd && stream.checkEOF() && stream.getPosition() == entryStart)
        {
            noteMissingGzipTrailer(entries);
            return std::nullopt;
        }
        if (entries == 0)
            throw core::InputError(mrpt::format(
                "'%s' is not an MRPT rawlog: its first entry cannot be read (%s); a TUM RGB-D "
                "folder is given as the folder itself",
                path.c_str(), innermostMrptMessage(e.what()).c_str()));
        // A recording cut short (or damaged) mid-entry: what came before it still counts.
        damage = mrpt::format(
            "rawlog '%s' is damaged or cut short at entry %zu (about byte %llu of %llu): %s",
            path.c_str(), entries + 1, static_cast<unsigned long long>(stream.getPosition()),
            static_cast<unsigned long long>(fileSize), innermostMrptMessage(e.what()).c_str());
        return std::nullopt;
    }
    entries++;
    return obj;
}

void RawlogSource::Impl::queueIfUsable(const CObservation3DRangeScan::Ptr& scan, COutputLogger& log)
{
    if (label && scan->sensorLabel != *label)
    {
        if (++rgbdOtherLabel == 1 && params.rawlog_sensor_label.empty())
            log.logFmt(mrpt::system::LVL_WARN,
                       "rawlog '%s' entry %zu: RGB-D observations from another sensor ('%s'); "
                       "reading only '%s', the first one seen (choose with [rawlog] "
                       "sensor_label)",
                       path.c_str(), entries, scan->sensorLabel.c_str(), label->c_str());
        return;
    }
    if (!scan->hasRangeImage || !scan->hasIntensityImage)
    {
        if (++rgbdWithoutImages == 1)
            log.logFmt(mrpt::system::LVL_WARN,
                       "rawlog '%s' entry %zu: CObservation3DRangeScan '%s' lacks a range or "
                       "intensity image; skipped (reported once)",
                       path.c_str(), entries, scan->sensorLabel.c_str());
        return;
    }
    if (!label)
        label = scan->sensorLabel;
    pending.push_back(scan);
}

void RawlogSource::Impl::noteMissingGzipTrailer(size_t entriesRead)
{
    const uint64_t read = stream.getPosition();
    if (!gzipDataSize || static_cast<uint32_t>(read) == *gzipDataSize)
        return;
    damage = mrpt::format(
        "rawlog '%s' is damaged or cut short at entry %zu: its compressed data ends after %llu "
        "bytes, where its gzip trailer says %u (mod 2^32)",
        path.c_str(), entriesRead + 1, static_cast<unsigned long long>(read), *gzipDataSize);
}

std::string RawlogSource::Impl::nothingUsable() const
{
    std::string found;
    for (const auto& [name, n] : classCounts)
        found += mrpt::format("%s%s x%zu", found.empty() ? "" : ", ", name.c_str(), n);
    std::string why;
    if (rgbdOtherLabel)
        why += mrpt::format("; %zu had a sensor label other than '%s'", rgbdOtherLabel,
                            params.rawlog_sensor_label.c_str());
    if (rgbdWithoutImages)
        why += mrpt::format("; %zu lacked range or intensity images", rgbdWithoutImages);
    if (!damage.empty())
        why += "; " + damage;
    return mrpt::format(
        "rawlog '%s' holds no usable RGB-D observation (mrpt::obs::CObservation3DRangeScan with "
        "range and intensity images); it contains: %s%s",
        path.c_str(), found.empty() ? "nothing" : found.c_str(), why.c_str());
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
    impl_->fileSize = fs::file_size(path);
    impl_->gzipDataSize = gzipTrailerSize(path, impl_->fileSize);
    impl_->archive.emplace(impl_->stream);
    // The converter's warnings (a camera size that differs from the images) go out as this
    // source's.
    impl_->converter.emplace(params, impl_->imagesDir);
    impl_->converter->logging_enable_console_output = false;
    impl_->converter->logRegisterCallback(
        [this](std::string_view msg, mrpt::system::VerbosityLevel level, std::string_view,
               mrpt::Clock::time_point) { logStr(level, msg); });
}

RawlogSource::~RawlogSource() = default;

std::optional<FrameRead> RawlogSource::read()
{
    if (impl_->ended)
        return std::nullopt;
    if (!impl_->fill(*this))
    {
        impl_->ended = true;
        if (impl_->frames == 0)
            throw core::InputError(impl_->nothingUsable());
        if (!impl_->damage.empty())
            MRPT_LOG_WARN_FMT("%s; stopped there: the %zu frames before it are processed",
                              impl_->damage.c_str(), impl_->frames);
        return std::nullopt;
    }
    auto obs = impl_->pending.front();
    impl_->pending.pop_front();
    const size_t index = impl_->frames++;
    try
    {
        auto frame = impl_->converter->convert(
            *obs, mrpt::format("rawlog '%s' entry %zu", impl_->path.c_str(), impl_->entries));
        frame.index = index;
        if (frame.name.empty())
            frame.name = mrpt::format("frame%06zu", index);
        return frame;
    }
    catch (const std::exception& e)  // InputError, or an image OpenCV cannot convert
    {
        return skip({index, mrpt::Clock::toDouble(obs->timestamp),
                     mrpt::format("frame%06zu", index),
                     mrpt::format("%s entry %zu", impl_->path.c_str(), impl_->entries),
                     innermostMrptMessage(e.what())});
    }
}

std::string RawlogSource::endedEarly() const
{
    return impl_->ended ? impl_->damage : std::string();
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

// A workaround for MRPT 2.5, which can crash on a damaged rawlog: its aligned_allocator uses the
// pointer mrpt::aligned_malloc() returns without checking it, so a corrupt range-image size
// (a flipped bit asking for terabytes) makes rangeImage_setSize() write through a null pointer.
// The definition below of mrpt::aligned_malloc takes precedence over libmrpt-core's in every
// program that links smap::io: libsmap_io comes before the MRPT libraries in the program's
// symbol lookup order, so MRPT's own calls bind to it (LD_DEBUG=bindings shows it). It
// allocates as MRPT's does (aligned, size rounded up to the alignment) but throws std::bad_alloc
// when the allocation fails, which RawlogSource reports as damage. mrpt::aligned_free stays MRPT's:
// std::free, which releases these blocks too.
// It lives in this file, the reader of rawlogs, beside the code it protects.
void* mrpt::aligned_malloc(size_t size, size_t alignment)
{
    // As libmrpt-core 2.5: the size rounded up to a multiple of the alignment, aligned_alloc.
    size_t rounded = size;
    if (alignment != 0 && size % alignment != 0)
    {
        if (size > SIZE_MAX - alignment)
            throw std::bad_alloc();
        rounded = (size / alignment + 1) * alignment;
    }
    void* p = std::aligned_alloc(alignment, rounded);
    if (p == nullptr && rounded != 0)  // what MRPT would have written through
        throw std::bad_alloc();
    return p;
}
