// A scratch folder for one fuzzing process, made on first use and removed at exit: the frame
// source fuzzers write each input there as the files the real sources read.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace smap::fuzz
{
class FuzzFolder
{
public:
    explicit FuzzFolder(const std::string& name)
        : path_(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid())))
    {
        std::filesystem::create_directories(path_);
    }
    ~FuzzFolder()
    {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    FuzzFolder(const FuzzFolder&) = delete;
    FuzzFolder& operator=(const FuzzFolder&) = delete;

    std::string operator/(const std::string& relative) const { return (path_ / relative).string(); }
    std::string str() const { return path_.string(); }

    /// Writes `size` bytes at `data` as the file `relative`.
    void write(const std::string& relative, const uint8_t* data, size_t size) const
    {
        std::ofstream f(path_ / relative, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }

private:
    std::filesystem::path path_;
};
}  // namespace smap::fuzz
