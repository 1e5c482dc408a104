#include "smap/io/ImageFile.h"

#include <mrpt/core/format.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <opencv2/imgcodecs.hpp>
#include <system_error>

namespace fs = std::filesystem;

namespace smap::io
{
namespace
{
uint32_t bigEndian(const std::string& b, size_t at, size_t bytes)
{
    uint32_t v = 0;
    for (size_t i = 0; i < bytes; i++)
        v = (v << 8) | static_cast<uint8_t>(b[at + i]);
    return v;
}

std::optional<cv::Size> pngSize(const std::string& b)
{
    // Signature (8 bytes), then the IHDR chunk: length (4), "IHDR", width (4), height (4).
    if (b.size() < 24 || b.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || b.compare(12, 4, "IHDR") != 0)
        return std::nullopt;
    const uint32_t w = bigEndian(b, 16, 4), h = bigEndian(b, 20, 4);
    if (w > 1u << 20 || h > 1u << 20)
        return cv::Size(-1, -1);  // beyond any image: reported as a wrong size
    return cv::Size(static_cast<int>(w), static_cast<int>(h));
}

std::optional<cv::Size> jpegSize(const std::string& b)
{
    if (b.size() < 4 || static_cast<uint8_t>(b[0]) != 0xFF || static_cast<uint8_t>(b[1]) != 0xD8)
        return std::nullopt;
    // Markers after SOI: each FF xx with a 2-byte length, until a start-of-frame (C0-CF but
    // C4 DHT, C8 JPG, CC DAC), which holds precision (1), height (2), width (2).
    size_t at = 2;
    while (at + 4 <= b.size())
    {
        if (static_cast<uint8_t>(b[at]) != 0xFF)
            return std::nullopt;
        const auto marker = static_cast<uint8_t>(b[at + 1]);
        if (marker == 0xFF)
        {
            at++;  // fill byte
            continue;
        }
        const uint32_t length = bigEndian(b, at + 2, 2);
        const bool frame =
            marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
        if (frame)
        {
            if (at + 9 > b.size())
                return std::nullopt;
            return cv::Size(static_cast<int>(bigEndian(b, at + 7, 2)),
                            static_cast<int>(bigEndian(b, at + 5, 2)));
        }
        if (length < 2 || marker == 0xDA)
            return std::nullopt;  // malformed, or scan data before any frame header
        at += 2 + length;
    }
    return std::nullopt;
}

std::string describeSize(const cv::Size& s)
{
    return s.width < 0 ? std::string("an impossible size")
                       : mrpt::format("%dx%d", s.width, s.height);
}
}  // namespace

std::optional<cv::Size> imageSizeFromHeader(const std::string& bytes)
{
    if (auto s = pngSize(bytes))
        return s;
    return jpegSize(bytes);
}

namespace
{
/// Whether the bytes start like an image format a recording holds (PNG, JPEG, PNM, TIFF, BMP).
/// cv::imdecode picks its decoder from the content, whatever the file's name, and some of its
/// decoders abort the process on a damaged file (GDCM asserts on a DICOM-looking one): those
/// are never offered anything.
bool hasRecordingImageSignature(const std::string& b)
{
    const auto starts = [&b](std::initializer_list<unsigned char> magic)
    {
        if (b.size() < magic.size())
            return false;
        size_t i = 0;
        for (const unsigned char m : magic)
            if (static_cast<unsigned char>(b[i++]) != m)
                return false;
        return true;
    };
    return starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}) || starts({0xff, 0xd8, 0xff}) ||
           starts({'I', 'I', '*', 0}) || starts({'M', 'M', 0, '*'}) || starts({'B', 'M'}) ||
           (b.size() >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6');
}
}  // namespace

ImageFileRead readImageFile(const std::string& path, int flags, const cv::Size& expected)
{
    ImageFileRead r;
    std::error_code ec;
    if (!fs::exists(path, ec))
    {
        r.problem = "missing";
        return r;
    }
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
    std::string bytes(size > 0 ? static_cast<size_t>(size) : 0, '\0');
    if (size < 0 || !in.seekg(0) || !in.read(bytes.data(), size))
    {
        r.problem = "cannot be read";
        return r;
    }
    if (bytes.empty())
    {
        r.problem = "empty (0 bytes)";
        return r;
    }
    if (!hasRecordingImageSignature(bytes))
    {
        r.problem =
            mrpt::format("is not a PNG, JPEG, PNM, TIFF or BMP image (%zu bytes)", bytes.size());
        return r;
    }
    const auto header = imageSizeFromHeader(bytes);
    if (header && header->width < 0)
    {
        r.problem = "has an impossible size in its header";
        return r;
    }
    if (header && !expected.empty() && *header != expected)
    {
        r.problem = mrpt::format("is %s, expected %dx%d", describeSize(*header).c_str(),
                                 expected.width, expected.height);
        r.wrongSize = true;
        return r;
    }
    const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1,
                      const_cast<char*>(bytes.data()));  // imdecode only reads it
    try
    {
        r.image = cv::imdecode(raw, flags);
    }
    catch (const cv::Exception&)
    {
        r.image.release();
    }
    if (r.image.empty())
    {
        r.problem =
            mrpt::format("cannot be decoded (%zu bytes: truncated, or not an image)", bytes.size());
        return r;
    }
    if (!expected.empty() && r.image.size() != expected)
    {
        r.problem = mrpt::format("is %dx%d, expected %dx%d", r.image.cols, r.image.rows,
                                 expected.width, expected.height);
        r.wrongSize = true;
        r.image.release();
    }
    return r;
}
}  // namespace smap::io
