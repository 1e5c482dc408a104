#include "smap/core/AtomicFile.h"

#include <mrpt/core/format.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "smap/core/InputError.h"

namespace fs = std::filesystem;

namespace smap::core
{
std::string temporarySiblingPath(const std::string& path)
{
    const fs::path p(path);
    const std::string name =
        "." + p.stem().string() + ".tmp-" + std::to_string(::getpid()) + p.extension().string();
    return (p.parent_path() / name).string();
}

void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& writer)
{
    const std::string tmp = temporarySiblingPath(path);
    try
    {
        writer(tmp);
        if (!fs::exists(tmp))
            throw std::runtime_error(mrpt::format("writing '%s' produced no file", path.c_str()));
        fs::rename(tmp, path);
    }
    catch (...)
    {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
    }
}

void writeDirectoryAtomically(const std::string& dir,
                              const std::function<void(const std::string&)>& writer,
                              const ReplaceCheck& mayReplace)
{
    fs::path target = fs::path(dir).lexically_normal();
    if (target.filename().empty() && target.has_parent_path() && target != target.root_path())
        target = target.parent_path();  // "out/" is "out"
    const std::string name = target.filename().string();
    if (name.empty() || name == "." || name == "..")
        throw InputError(mrpt::format(
            "'%s' names no folder of its own to write (give a new name such as '%s/out')",
            dir.c_str(), dir.c_str()));
    if (fs::exists(fs::symlink_status(target)))
    {
        if (!fs::is_directory(fs::symlink_status(target)))
            throw InputError(
                mrpt::format("'%s' exists and is not a folder: it is left alone", target.c_str()));
        if (!fs::is_empty(target) && !(mayReplace && mayReplace(target.string())))
            throw InputError(mrpt::format(
                "folder '%s' exists and is not an earlier output of this tool: it is left alone "
                "(choose another name, or remove it)",
                target.c_str()));
    }
    const fs::path tmp = target.parent_path() /
                         ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
    fs::remove_all(tmp);
    if (std::error_code ec; !fs::create_directories(tmp, ec) || ec)
        throw InputError(mrpt::format("cannot write folder '%s': %s", target.c_str(),
                                      ec ? ec.message().c_str() : "it could not be created"));
    try
    {
        writer(tmp.string());
        fs::remove_all(target);
        fs::rename(tmp, target);
    }
    catch (...)
    {
        std::error_code ec;
        fs::remove_all(tmp, ec);
        throw;
    }
}

AtomicTextFile::AtomicTextFile(std::string path)
    : path_(std::move(path)), tmpPath_(temporarySiblingPath(path_))
{
    out_.open(tmpPath_, std::ios::out | std::ios::trunc);
    if (!out_)
        throw std::runtime_error(mrpt::format("cannot create output file '%s'", path_.c_str()));
}

AtomicTextFile::~AtomicTextFile()
{
    if (!committed_)
    {
        out_.close();
        std::error_code ec;
        fs::remove(tmpPath_, ec);
    }
}

void AtomicTextFile::commit()
{
    out_.flush();
    const bool ok = static_cast<bool>(out_);
    out_.close();
    if (!ok || out_.fail())
        throw std::runtime_error(mrpt::format("error while writing '%s'", path_.c_str()));
    fs::rename(tmpPath_, path_);
    committed_ = true;
}
}  // namespace smap::core
