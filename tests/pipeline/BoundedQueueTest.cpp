// BoundedQueue: order, capacity, waiting, dropping and closing, across threads.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "smap/pipeline/BoundedQueue.h"

using smap::pipeline::BoundedQueue;

TEST(BoundedQueue, KeepsOrderAndCapacity)
{
    BoundedQueue<int> q(2);
    EXPECT_TRUE(q.tryPush(1));
    EXPECT_TRUE(q.tryPush(2));
    EXPECT_FALSE(q.tryPush(3)) << "full";
    EXPECT_EQ(q.size(), 2u);
    EXPECT_EQ(q.highWater(), 2u);
    EXPECT_EQ(*q.pop(), 1);
    EXPECT_TRUE(q.tryPush(4));
    EXPECT_EQ(*q.pop(), 2);
    EXPECT_EQ(*q.pop(), 4);
    q.close();
    EXPECT_FALSE(q.pop().has_value());
    EXPECT_FALSE(q.tryPush(5)) << "closed";
}

TEST(BoundedQueue, PushWaitsForRoomAndPopDrainsAfterClose)
{
    BoundedQueue<int> q(1);
    ASSERT_TRUE(q.push(0));
    std::atomic<bool> pushed{false};
    bool waited = false;
    std::thread producer(
        [&]
        {
            q.push(1, &waited);
            pushed = true;
            q.close();
        });
    // The producer cannot finish until an item is taken.
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_FALSE(pushed.load());
    EXPECT_EQ(*q.pop(), 0);
    EXPECT_EQ(*q.pop(), 1) << "items pushed before close are still delivered";
    producer.join();
    EXPECT_TRUE(pushed.load());
    EXPECT_TRUE(waited);
    EXPECT_FALSE(q.pop().has_value());
}

TEST(BoundedQueue, CloseWakesABlockedConsumerAndProducer)
{
    BoundedQueue<int> empty(1);
    std::thread consumer([&] { EXPECT_FALSE(empty.pop().has_value()); });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    empty.close();
    consumer.join();

    BoundedQueue<int> full(1);
    ASSERT_TRUE(full.push(7));
    std::thread producer([&] { EXPECT_FALSE(full.push(8)) << "dropped: closed while waiting"; });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    full.close();
    producer.join();
    EXPECT_EQ(*full.pop(), 7);
    EXPECT_FALSE(full.pop().has_value());
}
