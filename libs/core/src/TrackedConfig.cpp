#include "smap/core/TrackedConfig.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/system/string_utils.h>

#include <fstream>
#include <sstream>

#include "smap/core/InputError.h"

namespace smap::core
{
namespace
{
std::string keyId(const std::string& section, const std::string& key)
{
    return mrpt::system::lowerCase(section) + "/" + mrpt::system::lowerCase(key);
}

/// Converts the YAML subset a configuration needs - top-level sections holding "key: value"
/// pairs, plus unscoped top-level pairs - into INI text. Errors name source and line.
std::string yamlToIni(const std::string& yaml, const std::string& source)
{
    std::istringstream in(yaml);
    std::string line, unscoped, sections, current;
    size_t lineNo = 0;
    while (std::getline(in, line))
    {
        lineNo++;
        // Drop comments (a '#' at the start or after a space) and trailing whitespace.
        char quote = 0;
        for (size_t i = 0; i < line.size(); i++)
        {
            const char c = line[i];
            if (quote != 0)
            {
                if (c == quote)
                    quote = 0;
            }
            else if (c == '"' || c == '\'')
            {
                quote = c;
            }
            else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t'))
            {
                line.resize(i);
                break;
            }
        }
        const std::string trimmed = mrpt::system::trim(line);
        if (trimmed.empty() || trimmed == "---" || trimmed == "...")
            continue;
        const bool indented = line[0] == ' ' || line[0] == '\t';
        const auto colon = trimmed.find(':');
        if (colon == std::string::npos || colon == 0)
            throw InputError(mrpt::format("%s:%zu: expected 'key: value' or 'section:'",
                                          source.c_str(), lineNo));
        const std::string key = mrpt::system::trim(trimmed.substr(0, colon));
        std::string value = mrpt::system::trim(trimmed.substr(colon + 1));
        if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') &&
            value.back() == value.front())
            value = value.substr(1, value.size() - 2);
        if (!indented && value.empty())
        {
            current = key;
            sections += "[" + key + "]\n";
        }
        else if (!indented)
        {
            current.clear();
            unscoped.append(key).append(" = ").append(value).append("\n");
        }
        else if (current.empty())
        {
            throw InputError(mrpt::format("%s:%zu: indented key '%s' outside a section",
                                          source.c_str(), lineNo, key.c_str()));
        }
        else
        {
            if (value.empty() && trimmed.back() == ':')
                throw InputError(
                    mrpt::format("%s:%zu: nested section '%s' (only two levels are supported)",
                                 source.c_str(), lineNo, key.c_str()));
            sections.append(key).append(" = ").append(value).append("\n");
        }
    }
    return unscoped + sections;
}

bool endsWith(const std::string& s, const std::string& suffix)
{
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

void TrackedConfig::loadFile(const std::string& path)
{
    std::ifstream f(path);
    if (!f)
        throw InputError(mrpt::format("cannot open config file '%s'", path.c_str()));
    std::stringstream ss;
    ss << f.rdbuf();
    sourceName_ = path;
    const std::string lower = mrpt::system::lowerCase(path);
    if (endsWith(lower, ".yaml") || endsWith(lower, ".yml"))
    {
        setContentChecked(yamlToIni(ss.str(), path));
    }
    else
    {
        setContentChecked(ss.str());
    }
}

void TrackedConfig::setContentChecked(const std::string& iniText)
{
    try
    {
        setContent(iniText);
    }
    catch (const std::exception& e)
    {
        throw InputError(mrpt::format("config '%s': %s", sourceName_.c_str(),
                                      mrpt::exception_to_str(e).c_str()));
    }
}

void TrackedConfig::loadText(const std::string& iniText, const std::string& sourceName)
{
    sourceName_ = sourceName;
    setContentChecked(iniText);
}

void TrackedConfig::load(mrpt::config::CLoadableOptions& params, const std::string& section) const
{
    try
    {
        params.loadFromConfigFile(*this, section);
    }
    catch (const InputError& e)
    {
        throw InputError(mrpt::format("config '%s': %s", sourceName_.c_str(), e.what()));
    }
    catch (const std::exception& e)
    {
        throw InputError(mrpt::format("config '%s': %s", sourceName_.c_str(),
                                      mrpt::exception_to_str(e).c_str()));
    }
}

void TrackedConfig::loadYamlText(const std::string& yamlText, const std::string& sourceName)
{
    sourceName_ = sourceName;
    setContentChecked(yamlToIni(yamlText, sourceName));
}

void TrackedConfig::mergeFile(const std::string& path)
{
    TrackedConfig other;
    other.loadFile(path);
    std::vector<std::string> sections, keys;
    other.getAllSections(sections);
    for (const auto& section : sections)
    {
        other.getAllKeys(section, keys);
        for (const auto& key : keys)
            write(section, key, other.CConfigFileMemory::readString(section, key, ""));
    }
    sourceName_ += " + " + path;
}

void TrackedConfig::applyOverride(const std::string& assignment)
{
    const auto eq = assignment.find('=');
    const auto dot = assignment.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= eq)
    {
        throw InputError(
            mrpt::format("--set '%s': expected section.key=value, e.g. --set tum.depth_factor=1000",
                         assignment.c_str()));
    }
    const std::string section = mrpt::system::trim(assignment.substr(0, dot));
    const std::string key = mrpt::system::trim(assignment.substr(dot + 1, eq - dot - 1));
    const std::string value = mrpt::system::trim(assignment.substr(eq + 1));
    try
    {
        write(section, key, value);
    }
    catch (const std::exception& e)
    {
        throw InputError(
            mrpt::format("--set '%s': %s", assignment.c_str(), mrpt::exception_to_str(e).c_str()));
    }
    // Errors found later (unknown keys, bad values) then name --set among the sources.
    if (sourceName_.size() < 8 || sourceName_.compare(sourceName_.size() - 8, 8, " + --set") != 0)
        sourceName_ += " + --set";
}

std::string TrackedConfig::readString(const std::string& section, const std::string& name,
                                      const std::string& defaultStr, bool failIfNotFound) const
{
    readKeys_.insert(keyId(section, name));
    return CConfigFileMemory::readString(section, name, defaultStr, failIfNotFound);
}

std::vector<std::pair<std::string, std::string>> TrackedConfig::unusedKeys() const
{
    std::vector<std::pair<std::string, std::string>> unused;
    std::vector<std::string> sections;
    getAllSections(sections);
    for (const auto& s : sections)
    {
        std::vector<std::string> keys;
        getAllKeys(s, keys);
        for (const auto& k : keys)
        {
            if (readKeys_.count(keyId(s, k)) == 0)
                unused.emplace_back(s, k);
        }
    }
    return unused;
}

void TrackedConfig::ensureAllKeysUsed() const
{
    const auto unused = unusedKeys();
    if (unused.empty())
        return;
    std::string msg = mrpt::format("config '%s': unknown key(s):", sourceName_.c_str());
    for (const auto& [section, key] : unused)
    {
        std::string valid;
        const std::string prefix = mrpt::system::lowerCase(section) + "/";
        for (const auto& id : readKeys_)
        {
            if (id.compare(0, prefix.size(), prefix) == 0)
                valid += (valid.empty() ? "" : ", ") + id.substr(prefix.size());
        }
        msg +=
            mrpt::format("\n  [%s] %s  (valid keys in [%s]: %s)", section.c_str(), key.c_str(),
                         section.c_str(), valid.empty() ? "none: unknown section" : valid.c_str());
    }
    throw InputError(msg);
}
}  // namespace smap::core
