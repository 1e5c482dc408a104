// RawlogWriter: an observations-only rawlog MRPT's CRawlog reads back, written atomically.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>

#include <filesystem>

#include "TestData.h"
#include "smap/io/RawlogWriter.h"

using namespace smap;
namespace fs = std::filesystem;

namespace
{
size_t filesIn(const std::string& dir)
{
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir))
        n++;
    return n;
}
}  // namespace

TEST(RawlogWriter, WritesARawlogCRawlogReadsBackOnlyOnCommit)
{
    test::TempDir dir;
    const std::string path = dir / "out.rawlog";
    for (const int level : {0, 1})
    {
        {
            io::RawlogWriter w(path, level);
            for (int i = 0; i < 3; ++i)
            {
                // (Not CObservationComment: CRawlog takes that as the rawlog's comment.)
                mrpt::obs::CObservationOdometry c;
                c.odometry = mrpt::poses::CPose2D(i, 0.0, 0.0);
                c.timestamp = mrpt::Clock::fromDouble(100.0 + i);
                w.write(c);
            }
            EXPECT_EQ(w.entries(), 3u);
            EXPECT_FALSE(fs::exists(path)) << "nothing under the final name before commit";
            w.commit();
        }
        mrpt::obs::CRawlog log;
        ASSERT_TRUE(log.loadFromRawLogFile(path)) << "gzip level " << level;
        ASSERT_EQ(log.size(), 3u);
        auto c =
            std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(log.getAsObservation(2));
        ASSERT_TRUE(c);
        EXPECT_EQ(c->odometry.x(), 2.0);
        fs::remove(path);
    }
    // Dropped without commit (an exception mid-run): nothing is left, not even the temporary.
    {
        io::RawlogWriter w(path);
        w.write(mrpt::obs::CObservationOdometry());
    }
    EXPECT_EQ(filesIn(dir.str()), 0u);
    EXPECT_THROW(io::RawlogWriter(dir / "no/such/dir/x.rawlog"), std::runtime_error);
}
