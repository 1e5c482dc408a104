#include "smap/io/InputPreset.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <system_error>

#include "EmbeddedPresets.h"
#include "smap/core/InputError.h"

namespace fs = std::filesystem;

namespace smap::io
{
namespace
{
struct NameRule
{
    const char* tag;
    const char* file;
    const char* dataset;
};
constexpr std::array<NameRule, 7> kNameRules{{
    {"freiburg1", "tum_fr1.ini", "TUM RGB-D freiburg1"},
    {"freiburg2", "tum_fr2.ini", "TUM RGB-D freiburg2"},
    {"freiburg3", "tum_fr3.ini", "TUM RGB-D freiburg3"},
    {"7scenes", "7scenes.ini", "Microsoft 7-Scenes"},
    {"7-scenes", "7scenes.ini", "Microsoft 7-Scenes"},
    {"7_scenes", "7scenes.ini", "Microsoft 7-Scenes"},
    {"rgbd_bonn", "bonn.ini", "Bonn RGB-D Dynamic"},
}};

std::optional<InputPreset> ownCameraFile(const fs::path& folder)
{
    const fs::path path = folder / kFolderCameraFile;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        return std::nullopt;
    std::ifstream in(path);
    if (!in)  // e.g. no read permission: say so rather than apply an empty preset
        throw core::InputError("cannot open config file '" + path.string() + "'");
    std::ostringstream text;
    text << in.rdbuf();
    return InputPreset{path.string(),
                       "the folder carries its own " + std::string(kFolderCameraFile), text.str()};
}
}  // namespace

std::optional<InputPreset> presetForInput(const std::string& input)
{
    std::error_code ec;
    if (input.empty() || !fs::is_directory(input, ec))
        return std::nullopt;
    fs::path path(input);
    if (auto own = ownCameraFile(path))
        return own;
    if (isSmapSynthOutput(input))
        return std::nullopt;

    if (!path.has_filename())  // "dir/" -> "dir"
        path = path.parent_path();
    std::string name = path.filename().string();
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    const NameRule* match = nullptr;
    for (const auto& rule : kNameRules)
    {
        if (name.find(rule.tag) == std::string::npos)
            continue;
        if (match != nullptr && std::string_view(match->file) != rule.file)
            return std::nullopt;  // the name says two datasets: no guess
        match = &rule;
    }
    if (match == nullptr)
        return std::nullopt;
    return InputPreset{std::string("config/") + match->file,
                       std::string("its name says ") + match->dataset,
                       std::string(detail::embeddedPresetText(match->file))};
}

bool isSmapSynthOutput(const std::string& folder)
{
    std::ifstream meta(fs::path(folder) / "meta.json");
    std::string text((std::istreambuf_iterator<char>(meta)), std::istreambuf_iterator<char>());
    text.erase(std::remove_if(text.begin(), text.end(),
                              [](unsigned char ch) { return std::isspace(ch) != 0; }),
               text.end());
    return text.find(R"("generator":"smap-synth")") != std::string::npos;
}
}  // namespace smap::io
