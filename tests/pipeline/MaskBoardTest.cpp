// The mask board: a frame gets the newest mask up to its bound, waits for a late one that was
// announced, and never waits once the board is closed.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "TestData.h"
#include "smap/pipeline/MaskBoard.h"

using namespace smap;
using pipeline::MaskBoard;

namespace
{
MaskBoard::MaskPtr maskOf(uint64_t frameId)
{
    const cv::Mat labels(48, 64, CV_8UC1, cv::Scalar(0));
    const cv::Mat depth(48, 64, CV_32FC1, cv::Scalar(2.0F));
    core::PinholeCamera c;
    c.width = 64;
    c.height = 48;
    c.fx = c.fy = 50.0;
    c.cx = 31.5;
    c.cy = 23.5;
    return std::make_shared<const dynamic::MovableMask>(
        frameId, Eigen::Isometry3d::Identity(), labels, depth, c, std::vector<bool>(21, false), 4);
}
}  // namespace

TEST(MaskBoard, NewestUpToTheBound)
{
    MaskBoard board;
    EXPECT_EQ(board.newest(100, false).mask, nullptr);
    board.expect(3);
    board.publish(maskOf(3));
    board.expect(20);
    board.publish(maskOf(20));
    EXPECT_EQ(board.newest(19, true).mask->frameId(), 3U);
    EXPECT_EQ(board.newest(20, true).mask->frameId(), 20U);
    EXPECT_EQ(board.newest(2, true).mask, nullptr);
}

TEST(MaskBoard, WaitsForAnAnnouncedMaskOnlyWhenAsked)
{
    MaskBoard board;
    board.expect(5);
    // Without waiting: nothing yet.
    EXPECT_EQ(board.newest(10, false).mask, nullptr);
    // A bound before the announced keyframe does not wait.
    EXPECT_EQ(board.newest(4, true).wait_ms, 0.0);
    std::thread worker(
        [&]
        {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            board.publish(maskOf(5));
        });
    const MaskBoard::Lookup l = board.newest(10, true);
    worker.join();
    ASSERT_NE(l.mask, nullptr);
    EXPECT_EQ(l.mask->frameId(), 5U);
    EXPECT_GT(l.wait_ms, 0.0);
}

TEST(MaskBoard, PublishedBeforeAnnouncedAndClosedNeverWait)
{
    MaskBoard board;
    board.publish(maskOf(8));  // the worker was faster than the announcement
    board.expect(8);
    EXPECT_EQ(board.newest(9, true).mask->frameId(), 8U);
    board.expect(12);
    board.close();  // e.g. the worker failed: the mask of 12 never comes
    const MaskBoard::Lookup l = board.newest(30, true);
    EXPECT_EQ(l.mask->frameId(), 8U);
}
