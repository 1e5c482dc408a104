// A Parameters struct's configuration keys, listed once: loading and saving walk the same list,
// so a key cannot be read under one name and written under another, or forgotten in one of them.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace mrpt::config
{
class CConfigFileBase;
}

namespace smap::core
{
class OptionFields
{
public:
    /// `section` is the one the struct was given, or `ownSection` when that is empty.
    OptionFields(const std::string& section, const char* ownSection)
        : section_(section.empty() ? ownSection : section)
    {
    }

    OptionFields& add(const char* key, double& value) { return push(key, &value); }
    OptionFields& add(const char* key, int& value) { return push(key, &value); }
    OptionFields& add(const char* key, bool& value) { return push(key, &value); }
    OptionFields& add(const char* key, std::string& value) { return push(key, &value); }
    /// An enum kept as text in the file: parsed once, on load; an unknown name is an InputError
    /// that lists the valid ones.
    template <class Enum>
    OptionFields& addEnum(const char* key, Enum& value,
                          std::initializer_list<std::pair<const char*, Enum>> names)
    {
        EnumField f;
        f.target = &value;
        f.get = [](const void* p) { return static_cast<int>(*static_cast<const Enum*>(p)); };
        f.set = [](void* p, int v) { *static_cast<Enum*>(p) = static_cast<Enum>(v); };
        f.names = enumNames_.size();
        enumNames_.emplace_back();
        for (const auto& [name, v] : names)
            enumNames_.back().emplace_back(name, static_cast<int>(v));
        return push(key, f);
    }

    void load(const mrpt::config::CConfigFileBase& cfg) const;
    void save(mrpt::config::CConfigFileBase& cfg) const;
    const std::string& section() const { return section_; }

private:
    struct EnumField
    {
        void* target = nullptr;
        int (*get)(const void*) = nullptr;
        void (*set)(void*, int) = nullptr;
        size_t names = 0;  ///< index into enumNames_
    };
    using Target = std::variant<double*, int*, bool*, std::string*, EnumField>;
    struct Field
    {
        const char* key;
        Target target;
    };

    OptionFields& push(const char* key, Target target)
    {
        fields_.push_back({key, target});
        return *this;
    }

    std::string section_;
    std::vector<Field> fields_;
    std::vector<std::vector<std::pair<std::string, int>>> enumNames_;  ///< text of each enum
};
}  // namespace smap::core
