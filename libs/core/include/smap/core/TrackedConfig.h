// A configuration (INI or YAML) that remembers which keys the components read, so that a key
// nobody reads - a typo, an option of another version - is reported instead of ignored.
#pragma once

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/config/CLoadableOptions.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

namespace smap::core
{
class TrackedConfig : public mrpt::config::CConfigFileMemory
{
public:
    TrackedConfig() = default;

    /// Loads an INI file, or YAML (see loadYamlText) when the extension is .yaml/.yml. Throws
    /// InputError naming the file when it cannot be read or parsed.
    void loadFile(const std::string& path);
    /// Loads INI text; `sourceName` is used in error messages.
    void loadText(const std::string& iniText, const std::string& sourceName);
    /// Loads YAML text: top-level sections of "key: value" pairs (two levels, as INI).
    void loadYamlText(const std::string& yamlText, const std::string& sourceName);
    /// Loads another file (INI or YAML) on top: its keys replace or add to the present ones.
    void mergeFile(const std::string& path);
    /// Applies "section.key=value" (as given to --set); sourceName() then ends in " + --set".
    /// Throws InputError when malformed.
    void applyOverride(const std::string& assignment);

    const std::string& sourceName() const { return sourceName_; }

    /// Fills `params` from this configuration. Any failure (a bad value, a parse error inside
    /// MRPT) becomes core::InputError prefixed with the configuration's source name.
    void load(mrpt::config::CLoadableOptions& params, const std::string& section = {}) const;

    /// Throws InputError listing every key present in the configuration that no component
    /// read, with the keys that are valid in its section.
    void ensureAllKeysUsed() const;
    /// The (section, key) pairs present but never read; empty when all were used.
    std::vector<std::pair<std::string, std::string>> unusedKeys() const;

protected:
    std::string readString(const std::string& section, const std::string& name,
                           const std::string& defaultStr,
                           bool failIfNotFound = false) const override;

private:
    void setContentChecked(const std::string& iniText);

    std::string sourceName_ = "(built-in defaults)";
    /// "section/key" in lower case. Mutable: reading is logically const for callers.
    mutable std::set<std::string> readKeys_;
};
}  // namespace smap::core
