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
    const auto earlierOutput = [](const std::string& d) { return fs::exists(d + "/old.txt"); };
    try
    {
        smap::core::writeDirectoryAtomically(
            target,
            [](const std::string& tmp)
            {
                std::ofstream(tmp + "/half.txt") << "x";
                throw std::runtime_error("disk full");
            },
            earlierOutput);
        ADD_FAILURE() << "the writer's error was swallowed";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_STREQ(e.what(), "disk full");
    }
    EXPECT_TRUE(fs::exists(target + "/old.txt"));
    EXPECT_EQ(countFiles(dir.str()), 1u);  // no temporary folder left

    smap::core::writeDirectoryAtomically(
        target, [](const std::string& tmp) { std::ofstream(tmp + "/new.txt") << "new"; },
        earlierOutput);
    EXPECT_FALSE(fs::exists(target + "/old.txt"));
    EXPECT_EQ(smap::test::readTextFile(target + "/new.txt"), "new");
    EXPECT_EQ(countFiles(dir.str()), 1u);
}

TEST(AtomicFile, DirectoryNeverReplacesWhatItDidNotWrite)
{
    // `smap-synth --out .` once emptied the working folder: a user's file, a foreign folder,
    // "." and ".." are refused before the writer runs, and nothing is touched.
    smap::test::TempDir dir;
    std::ofstream(dir / "file.txt") << "keep";
    fs::create_directories(dir / "theirs");
    std::ofstream(dir / "theirs/data.txt") << "keep";
    int writes = 0;
    const auto writer = [&](const std::string& tmp)
    {
        ++writes;
        std::ofstream(tmp + "/new.txt") << "new";
    };
    const auto refusal = [&](const std::string& target) {
        return smap::test::inputErrorOf([&]
                                        { smap::core::writeDirectoryAtomically(target, writer); });
    };
    EXPECT_NE(refusal(dir / "file.txt").find("is not a folder"), std::string::npos);
    EXPECT_NE(refusal(dir / "theirs").find("not an earlier output"), std::string::npos);
    EXPECT_NE(refusal(dir / "theirs/").find("not an earlier output"), std::string::npos);
    EXPECT_NE(refusal(dir / "theirs/.").find("not an earlier output"), std::string::npos);
    EXPECT_NE(refusal(dir / "theirs/..").find("not an earlier output"), std::string::npos);
    EXPECT_NE(refusal(".").find("names no folder"), std::string::npos);
    EXPECT_NE(refusal("./").find("names no folder"), std::string::npos);
    EXPECT_NE(refusal("..").find("names no folder"), std::string::npos);
    EXPECT_NE(refusal("/").find("names no folder"), std::string::npos);
    EXPECT_EQ(writes, 0);
    EXPECT_EQ(smap::test::readTextFile(dir / "file.txt"), "keep");
    EXPECT_EQ(smap::test::readTextFile(dir / "theirs/data.txt"), "keep");
    EXPECT_EQ(countFiles(dir.str()), 2u);

    // An empty folder is replaced; a refused one is, once the check accepts it.
    fs::create_directories(dir / "empty");
    smap::core::writeDirectoryAtomically(dir / "empty", writer);
    smap::core::writeDirectoryAtomically(dir / "theirs", writer,
                                         [](const std::string&) { return true; });
    EXPECT_EQ(writes, 2);
    EXPECT_TRUE(fs::exists(dir / "empty/new.txt"));
    EXPECT_FALSE(fs::exists(dir / "theirs/data.txt"));
}
