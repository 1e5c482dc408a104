#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "SyntheticRgbd.h"
#include "TestData.h"
#include "smap/core/InputError.h"
#include "smap/pipeline/Tum2RawlogApp.h"

using namespace smap;

TEST(Tum2RawlogApp, ConvertsWithConfiguredCamera)
{
    test::TempDir dir;
    test::writeTumFolder(dir / "tum", 3, 0.0, false);
    std::ofstream(dir / "cam.ini")
        << "[camera]\nwidth = 64\nheight = 48\nfx = 60\nfy = 60\ncx = 31.5\ncy = 23.5\n";
    std::ostringstream out;
    pipeline::Tum2RawlogApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    EXPECT_EQ(
        app.run({dir / "tum", dir / "x.rawlog", "--config", dir / "cam.ini", "--max-frames", "2"},
                out),
        0);
    EXPECT_NE(out.str().find("2 frames"), std::string::npos) << out.str();
    EXPECT_TRUE(std::filesystem::exists(dir / "x_groundtruth.txt"));
    EXPECT_THROW(app.run({dir / "tum"}, out), core::InputError);
    EXPECT_THROW(app.run({dir / "tum", dir / "y.rawlog", "--max-frames", "-1"}, out),
                 core::InputError);
}
