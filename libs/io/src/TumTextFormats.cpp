#include "smap/io/TumTextFormats.h"

#include <mrpt/core/format.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"

namespace smap::io
{
namespace
{
/// Splits a data line into fields; returns false for comments and blank lines.
bool splitLine(std::string line, std::vector<std::string>& fields)
{
    fields.clear();
    for (char& c : line)
    {
        if (c == ',' || c == '\t' || c == '\r')
            c = ' ';
    }
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos || line[first] == '#')
        return false;
    std::istringstream ss(line);
    std::string f;
    while (ss >> f)
        fields.push_back(f);
    return true;
}

[[noreturn]] void fail(const std::string& source, size_t line, const std::string& what)
{
    throw core::InputError(mrpt::format("%s:%zu: %s", source.c_str(), line, what.c_str()));
}

double parseNumber(const std::string& s, const std::string& source, size_t line, const char* what)
{
    double v = 0.0;
    const char* begin = s.data();
    const char* end = s.data() + s.size();
    const auto res = std::from_chars(begin, end, v);
    if (res.ec != std::errc() || res.ptr != end || !std::isfinite(v))
        fail(source, line, mrpt::format("%s '%s' is not a finite number", what, s.c_str()));
    return v;
}

/// Calls fn(fields, line) for every data line. With `badLines`, a line fn rejects (InputError)
/// is recorded there and left out; without, the error propagates.
template <typename Fn>
void forEachDataLine(std::istream& in, std::vector<std::string>* badLines, Fn&& fn)
{
    std::string line;
    std::vector<std::string> fields;
    size_t lineNo = 0;
    while (std::getline(in, line))
    {
        lineNo++;
        if (!splitLine(line, fields))
            continue;
        try
        {
            fn(fields, lineNo);
        }
        catch (const core::InputError& e)
        {
            if (badLines == nullptr)
                throw;
            badLines->emplace_back(e.what());
        }
    }
}

std::ifstream openOrThrow(const std::string& path)
{
    std::ifstream f(path);
    if (!f)
        throw core::InputError(mrpt::format("cannot open '%s'", path.c_str()));
    return f;
}

/// Shortest text that reads back to the same double; "0" for a negative zero.
std::string formatDouble(double v)
{
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof(buf), v + 0.0);
    return std::string(buf, res.ptr);
}

/// The same in plain decimals (no exponent), as TUM's files write timestamps.
std::string formatTimestamp(double t)
{
    char buf[400];  // the longest fixed-notation double
    const auto res = std::to_chars(buf, buf + sizeof(buf), t + 0.0, std::chars_format::fixed);
    return std::string(buf, res.ptr);
}
}  // namespace

std::vector<TumListEntry> parseTumList(std::istream& in, const std::string& sourceName,
                                       std::vector<std::string>* badLines)
{
    std::vector<TumListEntry> out;
    forEachDataLine(
        in, badLines,
        [&](const std::vector<std::string>& f, size_t line)
        {
            if (f.size() != 2)
            {
                fail(sourceName, line,
                     mrpt::format("expected 'timestamp filename', found %zu fields", f.size()));
            }
            out.push_back({parseNumber(f[0], sourceName, line, "timestamp"), f[1], line});
        });
    return out;
}

std::vector<TumAssociationEntry> parseTumAssociations(std::istream& in,
                                                      const std::string& sourceName,
                                                      std::vector<std::string>* badLines)
{
    std::vector<TumAssociationEntry> out;
    forEachDataLine(
        in, badLines,
        [&](const std::vector<std::string>& f, size_t line)
        {
            if (f.size() != 4)
            {
                fail(sourceName, line,
                     mrpt::format(
                         "expected 'rgb_timestamp rgb_file depth_timestamp depth_file', found "
                         "%zu fields",
                         f.size()));
            }
            TumAssociationEntry e;
            e.rgbTimestamp = parseNumber(f[0], sourceName, line, "rgb timestamp");
            e.rgbFile = f[1];
            e.depthTimestamp = parseNumber(f[2], sourceName, line, "depth timestamp");
            e.depthFile = f[3];
            e.line = line;
            out.push_back(std::move(e));
        });
    return out;
}

core::Trajectory parseTumTrajectory(std::istream& in, const std::string& sourceName)
{
    core::Trajectory out;
    forEachDataLine(
        in, nullptr,
        [&](const std::vector<std::string>& f, size_t line)
        {
            if (f.size() != 8)
            {
                fail(sourceName, line,
                     mrpt::format("expected 'timestamp tx ty tz qx qy qz qw', found %zu fields",
                                  f.size()));
            }
            double v[8];
            static constexpr const char* kNames[8] = {"timestamp", "tx", "ty", "tz",
                                                      "qx",        "qy", "qz", "qw"};
            for (int i = 0; i < 8; i++)
                v[i] = parseNumber(f[i], sourceName, line, kNames[i]);
            const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
            if (std::abs(qn - 1.0) > 1e-2)
            {
                fail(sourceName, line,
                     mrpt::format("quaternion norm is %g, expected 1 (qx qy qz qw order)", qn));
            }
            // Normalise away the rounding of the file's printed digits.
            const mrpt::math::CQuaternionDouble q(v[7] / qn, v[4] / qn, v[5] / qn, v[6] / qn);
            core::StampedPose p;
            p.timestamp = v[0];
            p.T_world_cam = mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(v[1], v[2], v[3], q));
            out.push_back(p);
        });
    return out;
}

std::vector<TumListEntry> readTumList(const std::string& path, std::vector<std::string>* badLines)
{
    auto f = openOrThrow(path);
    return parseTumList(f, path, badLines);
}

std::vector<TumAssociationEntry> readTumAssociations(const std::string& path,
                                                     std::vector<std::string>* badLines)
{
    auto f = openOrThrow(path);
    return parseTumAssociations(f, path, badLines);
}

core::Trajectory readTumTrajectory(const std::string& path)
{
    auto f = openOrThrow(path);
    return parseTumTrajectory(f, path);
}

std::string formatTumPose(const core::StampedPose& pose)
{
    const mrpt::poses::CPose3DQuat pq(pose.T_world_cam);
    const auto& q = pq.quat();
    const double sign = q.r() < 0 ? -1.0 : 1.0;  // q and -q are the same rotation
    std::string s = formatTimestamp(pose.timestamp);
    for (double v :
         {pq.x(), pq.y(), pq.z(), sign * q.x(), sign * q.y(), sign * q.z(), sign * q.r()})
        s += " " + formatDouble(v);
    return s;
}

void writeTumTrajectory(const std::string& path, const core::Trajectory& trajectory,
                        const std::string& comment)
{
    core::AtomicTextFile out(path);
    if (!comment.empty())
        out.stream() << "# " << comment << "\n";
    out.stream() << "# timestamp tx ty tz qx qy qz qw\n";
    for (const auto& p : trajectory)
        out.stream() << formatTumPose(p) << "\n";
    out.commit();
}
std::vector<std::string> referenceTrajectories(const std::string& groundTruth)
{
    if (groundTruth.empty())
        return {};
    const std::filesystem::path gt(groundTruth);
    const std::string prefix = gt.stem().string() + "_";
    std::vector<std::string> others;
    std::error_code ec;
    const auto folder = gt.parent_path().empty() ? std::filesystem::path(".") : gt.parent_path();
    for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    {
        const std::string name = e.path().filename().string();
        if (e.is_regular_file(ec) && e.path().extension() == ".txt" &&
            name.compare(0, prefix.size(), prefix) == 0)
            others.push_back(e.path().string());
    }
    std::sort(others.begin(), others.end());
    others.insert(others.begin(), groundTruth);
    return others;
}
}  // namespace smap::io
