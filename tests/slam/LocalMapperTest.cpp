// Local mapping's keyframe hand-over on its own thread: every keyframe is processed once, in
// the order tracking inserted it, and a loop correction holding processingMutex() keeps it still.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "KeyFrameFixtures.h"
#include "smap/slam/KeyFrame.h"
#include "smap/slam/LocalMapper.h"
#include "smap/slam/Map.h"

using namespace smap;

namespace
{
std::vector<std::shared_ptr<slam::KeyFrame>> keyframesAlongX(slam::Map& map, int n)
{
    std::vector<std::shared_ptr<slam::KeyFrame>> kfs;
    for (int k = 0; k < n; ++k)
    {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(0.1 * k, 0, 0);
        kfs.push_back(map.createKeyFrame(test::frameWithKeypoints(20, T)));
    }
    return kfs;
}

slam::LocalMappingParameters mapping(bool threaded)
{
    slam::LocalMappingParameters p;
    p.threaded = threaded;
    return p;
}
}  // namespace

TEST(LocalMapper, EveryKeyFrameIsProcessedOnceInOrderThreadedOrNot)
{
    for (const bool threaded : {false, true})
    {
        slam::Map map;
        slam::LocalMapper mapper(map, mapping(threaded));
        std::vector<uint64_t> handedOn;  // written by the worker, read after waitUntilIdle()
        mapper.setProcessedSink([&](const std::shared_ptr<slam::KeyFrame>& kf)
                                { handedOn.push_back(kf->id()); });
        const auto kfs = keyframesAlongX(map, 12);
        std::vector<uint64_t> inserted;
        for (const auto& kf : kfs)
        {
            mapper.insertKeyFrame(kf);
            inserted.push_back(kf->id());
        }
        mapper.waitUntilIdle();
        EXPECT_TRUE(mapper.idle()) << "threaded " << threaded;
        EXPECT_EQ(mapper.queued(), 0U);
        EXPECT_EQ(handedOn, inserted) << "threaded " << threaded;
        EXPECT_EQ(mapper.stats().keyframesProcessed, kfs.size());
    }
}

TEST(LocalMapper, HoldingTheProcessingMutexKeepsItStill)
{
    slam::Map map;
    slam::LocalMapper mapper(map, mapping(true));
    const auto kfs = keyframesAlongX(map, 3);
    {
        std::lock_guard<std::mutex> still(mapper.processingMutex());
        for (const auto& kf : kfs)
            mapper.insertKeyFrame(kf);
        // The worker takes the first keyframe and waits for the mutex; the others queue.
        for (int i = 0; i < 2000 && !mapper.keyFrameWaiting(); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        EXPECT_TRUE(mapper.keyFrameWaiting().load());
        EXPECT_FALSE(mapper.idle());
        EXPECT_EQ(mapper.queued(), 2U);
        EXPECT_EQ(mapper.stats().keyframesProcessed, 0U);
    }
    mapper.waitUntilIdle();
    EXPECT_FALSE(mapper.keyFrameWaiting().load());
    EXPECT_EQ(mapper.stats().keyframesProcessed, 3U);
}
