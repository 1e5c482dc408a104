// Running the built commands as a user does, from the integration tests: exit code and output.
#pragma once

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "TestData.h"

namespace smap::test
{
struct CmdResult
{
    int code = -1;       ///< exit code; -1 when the command died of a signal
    std::string output;  // stdout and stderr
};

inline CmdResult run(const std::string& cmd)
{
    CmdResult r;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (!p)
        return r;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof(buf), p))
        r.output.append(buf, n);
    const int status = ::pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

inline std::string bin(const std::string& name)
{
    return binDir() + "/" + name;
}

/// The number after "key": in `json`, searching from the first occurrence of each of `path` in
/// turn (enough for our metrics.json); NaN when absent.
inline double jsonNumber(const std::string& json, const std::vector<std::string>& path)
{
    size_t at = 0;
    for (const auto& key : path)
    {
        at = json.find("\"" + key + "\":", at);
        if (at == std::string::npos)
            return std::nan("");
        at += key.size() + 3;
    }
    return std::strtod(json.c_str() + at, nullptr);
}
}  // namespace smap::test
