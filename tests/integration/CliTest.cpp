// The installed commands as a user runs them: exit codes and messages.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>

#include "TestData.h"

namespace
{
struct CmdResult
{
    int code = -1;
    std::string output;  // stdout and stderr
};

CmdResult run(const std::string& cmd)
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

std::string bin(const std::string& name)
{
    return smap::test::binDir() + "/" + name;
}
}  // namespace

TEST(Cli, MainJobRunsOnTheEmbeddedDefault)
{
    smap::test::TempDir dir;
    const CmdResult r = run(bin("semantic-mapper") + " --out " + (dir / "out"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("outputs in"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("200 frames from"), std::string::npos) << r.output;
    EXPECT_TRUE(std::ifstream(dir / "out/summary.json").good());
}

TEST(Cli, BadInputExitsWithCodeTwoAndNamesTheProblem)
{
    smap::test::TempDir dir;
    CmdResult r = run(bin("semantic-mapper") + " " + (dir / "no-such-input"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("no-such-input"), std::string::npos) << r.output;

    std::ofstream(dir / "gt.txt") << "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n";
    r = run(bin("smap-eval") + " ate " + (dir / "gt.txt") + " " + (dir / "gt.txt"));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("gt.txt:2:"), std::string::npos) << r.output;

    r = run(bin("tum2rawlog") + " --bogus");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("unknown option '--bogus'"), std::string::npos) << r.output;

    r = run(bin("smap-eval") + " --help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("smap-eval ate GT EST"), std::string::npos);
}
