#include "smap/core/DataDirectory.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace fs = std::filesystem;

namespace smap::core
{
namespace
{
/// <prefix>/share/semantic-mapper for a binary in <prefix>/bin or <prefix>/lib.
fs::path besideBinary(const fs::path& binary)
{
    return (binary.parent_path().parent_path() / "share" / "semantic-mapper").lexically_normal();
}

fs::path runningExecutable()
{
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe;
}

/// The file of the shared library holding this function (libsmap_core), when the loader knows.
fs::path thisLibrary()
{
    Dl_info info{};
    if (dladdr(reinterpret_cast<const void*>(&besideBinary), &info) == 0 ||
        info.dli_fname == nullptr)
        return {};
    std::error_code ec;
    const fs::path p = fs::canonical(info.dli_fname, ec);
    return ec ? fs::path() : p;
}
}  // namespace

std::string dataDirectory()
{
    if (const char* env = std::getenv(kDataDirectoryVariable); env != nullptr && *env != '\0')
        return env;
    const fs::path exe = runningExecutable();
    std::error_code ec;
    if (!exe.empty() && fs::is_directory(besideBinary(exe), ec))
        return besideBinary(exe);
    // A program built elsewhere against the installed libraries: the data of their prefix.
    const fs::path lib = thisLibrary();
    if (!lib.empty() && fs::is_directory(besideBinary(lib), ec))
        return besideBinary(lib);
    return exe.empty() ? std::string() : besideBinary(exe).string();
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
