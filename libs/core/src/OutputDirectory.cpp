#include "smap/core/OutputDirectory.h"

#include <mrpt/core/format.h>

#include <filesystem>
#include <fstream>
#include <system_error>

#include "smap/core/AtomicFile.h"
#include "smap/core/InputError.h"

namespace fs = std::filesystem;

namespace smap::core
{
void prepareOutputDirectory(const std::string& dir, const std::string& option)
{
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
    {
        const std::string why = ec ? ec.message() : std::string("it is not a folder");
        throw InputError(mrpt::format("cannot use '%s' as the output folder (%s): %s", dir.c_str(),
                                      option.c_str(), why.c_str()));
    }
    // A probe file: permissions, read-only mounts and quotas all show up here.
    const std::string probe = temporarySiblingPath((fs::path(dir) / "write-test").string());
    {
        std::ofstream f(probe);
        if (!f)
            throw InputError(mrpt::format("output folder '%s' (%s) is not writable", dir.c_str(),
                                          option.c_str()));
    }
    fs::remove(probe, ec);
}
}  // namespace smap::core
