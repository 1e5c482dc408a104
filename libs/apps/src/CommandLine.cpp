#include "smap/apps/CommandLine.h"

#include <mrpt/core/format.h>

#include <cmath>
#include <cstdlib>

#include "smap/core/InputError.h"

namespace smap::apps
{
CommandLine& CommandLine::option(const std::string& name)
{
    options_.insert(name);
    return *this;
}

CommandLine& CommandLine::flag(const std::string& name)
{
    flags_.insert(name);
    return *this;
}

void CommandLine::parse(const std::vector<std::string>& args)
{
    for (size_t i = 0; i < args.size(); i++)
    {
        const std::string& a = args[i];
        if (a.size() < 3 || a.compare(0, 2, "--") != 0)
        {
            positionals_.push_back(a);
            continue;
        }
        std::string name = a.substr(2);
        std::optional<std::string> inlineValue;
        if (const auto eq = name.find('='); eq != std::string::npos)
        {
            inlineValue = name.substr(eq + 1);
            name = name.substr(0, eq);
        }
        if (flags_.count(name))
        {
            if (inlineValue)
                throw core::InputError(mrpt::format("option --%s takes no value", name.c_str()));
            flagsSeen_.insert(name);
        }
        else if (options_.count(name))
        {
            if (!inlineValue && i + 1 >= args.size())
                throw core::InputError(mrpt::format("option --%s needs a value", name.c_str()));
            values_[name].push_back(inlineValue ? *inlineValue : args[++i]);
        }
        else
        {
            throw core::InputError(mrpt::format("unknown option '%s' (see --help)", a.c_str()));
        }
    }
}

bool CommandLine::has(const std::string& name) const
{
    return flagsSeen_.count(name) != 0 || values_.count(name) != 0;
}

std::optional<std::string> CommandLine::value(const std::string& name) const
{
    const auto it = values_.find(name);
    if (it == values_.end() || it->second.empty())
        return std::nullopt;
    return it->second.back();
}

std::vector<std::string> CommandLine::values(const std::string& name) const
{
    const auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
}

double CommandLine::number(const std::string& name, double defaultValue) const
{
    const auto v = value(name);
    if (!v)
        return defaultValue;
    char* end = nullptr;
    const double d = std::strtod(v->c_str(), &end);
    if (v->empty() || *end != '\0' || !std::isfinite(d))
        throw core::InputError(mrpt::format("--%s '%s' is not a number", name.c_str(), v->c_str()));
    return d;
}

long CommandLine::integer(const std::string& name, long defaultValue) const
{
    const auto v = value(name);
    if (!v)
        return defaultValue;
    char* end = nullptr;
    const long n = std::strtol(v->c_str(), &end, 10);
    if (v->empty() || *end != '\0')
        throw core::InputError(
            mrpt::format("--%s '%s' is not an integer", name.c_str(), v->c_str()));
    return n;
}
}  // namespace smap::apps
