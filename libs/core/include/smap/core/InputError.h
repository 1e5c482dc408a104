// Error raised for bad user input (a file, a value, an option), as opposed to an internal
// failure: apps map it to a distinct exit code and print it without a backtrace.
#pragma once

#include <stdexcept>
#include <string>

namespace smap::core
{
class InputError : public std::runtime_error
{
public:
    explicit InputError(const std::string& what) : std::runtime_error(what) {}
};
}  // namespace smap::core
