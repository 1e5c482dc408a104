#include "smap/io/RangeImageFile.h"

#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "smap/core/InputError.h"

namespace smap::io
{
namespace
{
cv::Mat readText(const std::string& path)
{
    std::ifstream f(path);
    if (!f)
        throw core::InputError(mrpt::format("cannot open range image '%s'", path.c_str()));
    std::vector<std::vector<uint16_t>> rows;
    std::string line;
    while (std::getline(f, line))
    {
        std::istringstream ss(line);
        std::vector<uint16_t> row;
        double v = 0;
        while (ss >> v)
        {
            if (!(v >= 0.0 && v <= 65535.0))
                throw core::InputError(mrpt::format(
                    "range image '%s': value %g out of uint16 range", path.c_str(), v));
            row.push_back(static_cast<uint16_t>(std::lround(v)));
        }
        if (!row.empty())
            rows.push_back(std::move(row));
    }
    if (rows.empty())
        throw core::InputError(mrpt::format("range image '%s' is empty", path.c_str()));
    cv::Mat out(static_cast<int>(rows.size()), static_cast<int>(rows[0].size()), CV_16UC1);
    for (size_t r = 0; r < rows.size(); r++)
    {
        if (rows[r].size() != rows[0].size())
            throw core::InputError(
                mrpt::format("range image '%s': row %zu has %zu values, row 1 has %zu",
                             path.c_str(), r + 1, rows[r].size(), rows[0].size()));
        std::copy(rows[r].begin(), rows[r].end(), out.ptr<uint16_t>(static_cast<int>(r)));
    }
    return out;
}
}  // namespace

cv::Mat readExternalRangeImage(const std::string& path)
{
    if (!std::filesystem::exists(path))
        throw core::InputError(
            mrpt::format("external range image '%s' does not exist", path.c_str()));
    std::string ext = std::filesystem::path(path).extension().string();
    for (auto& c : ext)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".txt")
        return readText(path);

    mrpt::io::CFileGZInputStream fi;
    if (!fi.open(path))
        throw core::InputError(mrpt::format("cannot open range image '%s'", path.c_str()));
    auto arch = mrpt::serialization::archiveFrom(fi);
    try
    {
        const auto rows = arch.ReadAs<uint32_t>();
        const auto cols = arch.ReadAs<uint32_t>();
        if (rows == 0 || cols == 0 || rows > 16384 || cols > 16384)
            throw core::InputError(
                mrpt::format("range image '%s': implausible size %ux%u", path.c_str(), cols, rows));
        cv::Mat out(static_cast<int>(rows), static_cast<int>(cols), CV_16UC1);
        arch.ReadBufferFixEndianness<uint16_t>(out.ptr<uint16_t>(), out.total());
        return out;
    }
    catch (const core::InputError&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        throw core::InputError(
            mrpt::format("range image '%s' is truncated or corrupt: %s", path.c_str(), e.what()));
    }
}
}  // namespace smap::io
