#include "smap/sim/PersonSprite.h"

#include <mrpt/core/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "smap/core/InputError.h"

namespace fs = std::filesystem;

namespace smap::sim
{
namespace
{
cv::Mat readRgba(const fs::path& file, const std::string& where)
{
    cv::Mat image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    if (image.type() != CV_8UC4)
        throw core::InputError(
            mrpt::format("%s: '%s' is not an RGBA PNG", where.c_str(), file.string().c_str()));
    return image;
}

PersonSprite parseListLine(const fs::path& folder, const std::string& line,
                           const std::string& where)
{
    std::string fields[4];
    std::istringstream in(line);
    for (auto& f : fields)
    {
        if (!std::getline(in, f, ','))
            throw core::InputError(where + ": expected 'file,kind,min_height_m,max_height_m'");
    }
    PersonSprite s;
    s.file = (folder / fields[0]).string();
    if (fields[1] != "standing" && fields[1] != "sitting")
        throw core::InputError(where + ": kind '" + fields[1] + "' is not standing or sitting");
    s.posture =
        fields[1] == "sitting" ? PersonSprite::Posture::Sitting : PersonSprite::Posture::Standing;
    try
    {
        s.minHeight = std::stod(fields[2]);
        s.maxHeight = std::stod(fields[3]);
    }
    catch (const std::exception&)
    {
        throw core::InputError(where + ": heights '" + fields[2] + "', '" + fields[3] +
                               "' are not numbers");
    }
    if (!(s.minHeight > 0.3 && s.maxHeight >= s.minHeight && s.maxHeight < 2.5))
        throw core::InputError(where + ": heights must satisfy 0.3 < min <= max < 2.5 m");
    s.image = readRgba(s.file, where);
    return s;
}

std::vector<PersonSprite> readList(const fs::path& folder, const fs::path& list)
{
    std::ifstream in(list);
    if (!in)
        throw core::InputError("cannot open '" + list.string() + "'");
    std::vector<PersonSprite> sprites;
    std::string line;
    for (size_t lineNo = 1; std::getline(in, line); lineNo++)
    {
        line.erase(std::remove(line.begin(), line.end(), '\r'), line.end());
        if (line.empty() || line[0] == '#')
            continue;
        sprites.push_back(
            parseListLine(folder, line, mrpt::format("%s:%zu", list.string().c_str(), lineNo)));
    }
    return sprites;
}

std::vector<PersonSprite> readEveryPng(const fs::path& folder)
{
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(folder))
    {
        const std::string n = e.path().filename().string();
        if (n.rfind("person_", 0) == 0 && e.path().extension() == ".png")
            files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    std::vector<PersonSprite> sprites;
    for (const auto& f : files)
    {
        PersonSprite s;
        s.file = f.string();
        s.image = readRgba(f, "person cut-outs in '" + folder.string() + "'");
        sprites.push_back(std::move(s));
    }
    return sprites;
}
}  // namespace

std::vector<PersonSprite> loadPersonSprites(const std::string& folder)
{
    const fs::path dir(folder);
    if (folder.empty() || !fs::is_directory(dir))
        throw core::InputError(
            mrpt::format("person cut-outs: '%s' is not a folder", folder.c_str()));
    const fs::path list = dir / "people.csv";
    auto sprites = fs::exists(list) ? readList(dir, list) : readEveryPng(dir);
    if (sprites.empty())
        throw core::InputError(
            mrpt::format("no RGBA person_*.png cut-outs in '%s'", folder.c_str()));
    return sprites;
}
}  // namespace smap::sim
