// A small, strict command-line parser shared by the apps: positionals, "--name value" or
// "--name=value" options (repeatable where declared) and "--flag" switches. Anything
// undeclared is an error, so a typo never passes silently.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace smap::apps
{
class CommandLine
{
public:
    /// Declares options; names without the leading "--".
    CommandLine& option(const std::string& name);
    CommandLine& flag(const std::string& name);

    /// Throws core::InputError for an unknown option or a missing value.
    void parse(const std::vector<std::string>& args);

    const std::vector<std::string>& positionals() const { return positionals_; }
    bool has(const std::string& name) const;
    std::optional<std::string> value(const std::string& name) const;  ///< last occurrence
    std::vector<std::string> values(const std::string& name) const;   ///< all occurrences
    /// Typed accessors that name the option in their error.
    double number(const std::string& name, double defaultValue) const;
    long integer(const std::string& name, long defaultValue) const;

private:
    std::set<std::string> options_, flags_;
    std::vector<std::string> positionals_;
    std::map<std::string, std::vector<std::string>> values_;
    std::set<std::string> flagsSeen_;
};

/// Exit codes shared by every app.
enum ExitCode : int
{
    kExitOk = 0,
    kExitInternalError = 1,  ///< a bug or an environment failure (disk full, ...)
    kExitBadInput = 2,       ///< bad arguments, configuration or input data
    kExitInterrupted = 130,  ///< stopped by Ctrl-C / SIGTERM (outputs cover what was processed)
};
}  // namespace smap::apps
