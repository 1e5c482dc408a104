// smap-eval: trajectory metrics (ATE, RPE) from the command line, as TUM's tools compute them.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace smap::apps
{
class EvalApp
{
public:
    /// Arguments after the program name; returns an ExitCode, throws core::InputError.
    int run(const std::vector<std::string>& args, std::ostream& out);
    static std::string usage();
};
}  // namespace smap::apps
