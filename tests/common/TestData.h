// Helpers shared by the test suites: data locations, temporary folders, the ../shared rule.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "smap/core/InputError.h"
#include "smap/core/PinholeCamera.h"

namespace smap::test
{
/// A pinhole camera without distortion whose principal point is the image centre.
inline core::PinholeCamera centredCamera(int width, int height, double focal)
{
    core::PinholeCamera c;
    c.width = width;
    c.height = height;
    c.fx = c.fy = focal;
    c.cx = (width - 1) / 2.0;
    c.cy = (height - 1) / 2.0;
    return c;
}

inline std::string sharedDir()
{
    return SMAP_SHARED_DIR;
}
inline std::string sourceDir()
{
    return SMAP_SOURCE_DIR;
}
inline std::string binDir()
{
    return SMAP_BIN_DIR;
}
inline std::string mrptSampleRgbd()
{
    return SMAP_MRPT_SAMPLE_RGBD;
}
inline std::string sevenScenesDir()
{
    return sharedDir() + "/data/7scenes-redkitchen";
}

inline bool runningInCi()
{
    const char* ci = std::getenv("CI");
    return ci != nullptr && std::string(ci) == "true";
}

inline std::string readTextFile(const std::string& path)
{
    std::ifstream f(path);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// The message of the core::InputError that `fn` throws, or "(no error)".
template <typename Fn>
std::string inputErrorOf(Fn&& fn)
{
    try
    {
        fn();
    }
    catch (const core::InputError& e)
    {
        return e.what();
    }
    return "(no error)";
}

/// A fresh folder under the system temp dir, removed at scope exit.
class TempDir
{
public:
    TempDir()
    {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() /
                ("smap-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string str() const { return path_.string(); }
    std::string operator/(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};
}  // namespace smap::test

/// Skips the test when `path` (data from ../shared) is missing - but fails under CI=true, where
/// ../shared must be present.
#define SMAP_REQUIRE_DATA(path)                                              \
    do                                                                       \
    {                                                                        \
        if (!std::filesystem::exists(path))                                  \
        {                                                                    \
            if (smap::test::runningInCi())                                   \
                FAIL() << "required test data missing: " << (path);          \
            GTEST_SKIP() << "test data not found: " << (path)                \
                         << " (clone the project with ../shared beside it)"; \
        }                                                                    \
    } while (0)
