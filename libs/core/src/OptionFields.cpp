#include "smap/core/OptionFields.h"

#include <mrpt/config/CConfigFileBase.h>

#include "smap/core/InputError.h"

namespace smap::core
{
namespace
{
template <class... Ts>
struct Overloaded : Ts...
{
    using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;
}  // namespace

void OptionFields::load(const mrpt::config::CConfigFileBase& cfg) const
{
    const std::string& s = section_;
    for (const auto& f : fields_)
    {
        std::visit(
            Overloaded{
                [&](double* v) { *v = cfg.read_double(s, f.key, *v); },
                [&](int* v) { *v = cfg.read_int(s, f.key, *v); },
                [&](bool* v) { *v = cfg.read_bool(s, f.key, *v); },
                [&](std::string* v) { *v = cfg.read_string(s, f.key, *v); },
                [&](const EnumField& e)
                {
                    const auto& names = enumNames_[e.names];
                    std::string current, valid;
                    for (const auto& [name, value] : names)
                    {
                        if (value == e.get(e.target))
                            current = name;
                        valid.append(valid.empty() ? "" : ", ").append(name);
                    }
                    const std::string text = cfg.read_string(s, f.key, current);
                    for (const auto& [name, value] : names)
                        if (name == text)
                            return e.set(e.target, value);
                    std::string message = "[";
                    message.append(s).append("] ").append(f.key).append(" = '").append(text);
                    message.append("' is not one of: ").append(valid);
                    throw InputError(message);
                },
            },
            f.target);
    }
}

void OptionFields::save(mrpt::config::CConfigFileBase& cfg) const
{
    const std::string& s = section_;
    for (const auto& f : fields_)
    {
        std::visit(
            Overloaded{
                [&](double* v) { cfg.write(s, f.key, *v); },
                [&](int* v) { cfg.write(s, f.key, *v); },
                [&](bool* v) { cfg.write(s, f.key, *v); },
                [&](std::string* v) { cfg.write(s, f.key, *v); },
                [&](const EnumField& e)
                {
                    for (const auto& [name, value] : enumNames_[e.names])
                        if (value == e.get(e.target))
                            cfg.write(s, f.key, name);
                },
            },
            f.target);
    }
}
}  // namespace smap::core
