#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "TestData.h"
#include "smap/core/AtomicFile.h"

namespace fs = std::filesystem;

namespace
{
size_t countFiles(const std::string& dir)
{
    return static_cast<size_t>(
        std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}
}  // namespace

TEST(AtomicFile, CommitReplacesTarget)
{
    smap::test::TempDir dir;
    const std::string p = dir / "out.txt";
    {
        std::ofstream(p) << "old";
    }
    smap::core::AtomicTextFile f(p);
    f.stream() << "new";
    EXPECT_EQ(smap::test::readTextFile(p), "old");  // untouched until commit
    f.commit();
    EXPECT_EQ(smap::test::readTextFile(p), "new");
    EXPECT_EQ(countFiles(dir.str()), 1u);
}

TEST(AtomicFile, NoCommitLeavesNothing)
{
    smap::test::TempDir dir;
    {
        smap::core::AtomicTextFile f(dir / "out.txt");
        f.stream() << "partial";
    }
    EXPECT_EQ(countFiles(dir.str()), 0u);
}

TEST(AtomicFile, ThrowingWriterKeepsOldFile)
{
    smap::test::TempDir dir;
    const std::string p = dir / "plot.png";
    {
        std::ofstream(p) << "old";
    }
    EXPECT_THROW(smap::core::writeFileAtomically(p,
                                                 [](const std::string& tmp)
                                                 {
                                                     EXPECT_EQ(fs::path(tmp).extension(), ".png");
                                                     std::ofstream(tmp) << "half";
                                                     throw std::runtime_error("disk full");
                                                 }),
                 std::runtime_error);
    EXPECT_EQ(smap::test::readTextFile(p), "old");
    EXPECT_EQ(countFiles(dir.str()), 1u);
    EXPECT_THROW(smap::core::writeFileAtomically(dir / "none.txt", [](const std::string&) {}),
                 std::runtime_error);
}

TEST(AtomicFile, DirectoryReplacedOnlyWhenTheWriterSucceeds)
{
    smap::test::TempDir dir;
    const std::string target = dir / "seq";
    fs::create_directories(target);
    std::ofstream(target + "/old.txt") << "old";
    EXPECT_THROW(smap::core::writeDirectoryAtomically(target,
                                                      [](const std::string& tmp)
                                                      {
                                                          std::ofstream(tmp + "/half.txt") << "x";
                                                          throw std::runtime_error("disk full");
                                                      }),
                 std::runtime_error);
    EXPECT_TRUE(fs::exists(target + "/old.txt"));
    EXPECT_EQ(countFiles(dir.str()), 1u);  // no temporary folder left

    smap::core::writeDirectoryAtomically(
        target, [](const std::string& tmp) { std::ofstream(tmp + "/new.txt") << "new"; });
    EXPECT_FALSE(fs::exists(target + "/old.txt"));
    EXPECT_EQ(smap::test::readTextFile(target + "/new.txt"), "new");
    EXPECT_EQ(countFiles(dir.str()), 1u);
}
