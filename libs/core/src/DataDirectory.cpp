#include "smap/core/DataDirectory.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace fs = std::filesystem;

namespace smap::core
{
std::string dataDirectory()
{
    if (const char* env = std::getenv(kDataDirectoryVariable); env != nullptr && *env != '\0')
        return env;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec || exe.empty())
        return {};
    return (exe.parent_path().parent_path() / "share" / "semantic-mapper").lexically_normal();
}

std::string findDataFile(const std::string& relative)
{
    const std::string dir = dataDirectory();
    if (dir.empty())
        return {};
    const fs::path p = fs::path(dir) / relative;
    std::error_code ec;
    return fs::exists(p, ec) ? p.string() : std::string();
}
}  // namespace smap::core
