// The queue between the receiver and the estimator: fixed capacity, FIFO order across the ring's
// wrap-around, a full queue refusing without change, a pop that times out, and one producer and
// one consumer threads passing every item in order.
#include "inertial/runtime/bounded_queue.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

namespace inertial {
namespace {

// The queue itself: fixed capacity, a push into a full queue refused (the daemon counts it as a
// drop), order kept, a pop that times out.
TEST(BoundedQueue, RefusesWhenFullAndKeepsOrder) {
  BoundedQueue<int> q(4, 0);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.TryPush(i));
  EXPECT_FALSE(q.TryPush(99));
  EXPECT_EQ(q.size(), 4u);
  int v = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.PopWait(&v, std::chrono::milliseconds(0)));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(q.PopWait(&v, std::chrono::milliseconds(5)));
  EXPECT_TRUE(q.TryPush(7));
}

TEST(BoundedQueue, OrderHoldsAcrossTheWrapAround) {
  BoundedQueue<std::vector<double>> q(3, std::vector<double>(2, 0.0));
  EXPECT_EQ(q.capacity(), 3u);
  EXPECT_EQ(q.size(), 0u);
  int next_in = 0, next_out = 0;
  std::vector<double> v;
  for (int round = 0; round < 10; ++round) {  // push 2, pop 1, ... the ring's head goes round
    for (int k = 0; k < 2; ++k) {
      if (q.TryPush({static_cast<double>(next_in), -1.0})) ++next_in;
    }
    ASSERT_TRUE(q.PopWait(&v, std::chrono::milliseconds(0)));
    EXPECT_EQ(v[0], next_out++);
    EXPECT_LE(q.size(), 3u);
  }
  while (q.PopWait(&v, std::chrono::milliseconds(0))) EXPECT_EQ(v[0], next_out++);
  EXPECT_EQ(next_out, next_in);
  EXPECT_EQ(q.size(), 0u);
}

TEST(BoundedQueue, ProducerAndConsumerThreadsPassEveryItemInOrder) {
  BoundedQueue<int> q(8, 0);
  const int n = 20000;
  std::thread producer([&] {
    for (int i = 0; i < n; ++i) {
      while (!q.TryPush(i)) std::this_thread::yield();  // full: try again
    }
  });
  int expected = 0, v = -1;
  while (expected < n) {
    ASSERT_TRUE(q.PopWait(&v, std::chrono::milliseconds(5000)));
    ASSERT_EQ(v, expected);
    ++expected;
  }
  producer.join();
  EXPECT_FALSE(q.PopWait(&v, std::chrono::milliseconds(1)));
}

}  // namespace
}  // namespace inertial
