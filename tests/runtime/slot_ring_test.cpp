// The hand-over of inertiald's real-time threads to its sinks (slot_ring.hpp): a full ring refuses
// at once (the caller counts a drop), order is kept across the wrap-around, filling a slot of the
// prototype's sizes allocates nothing, one producer and one consumer pass every item in order, and
// a consumer that sleeps never holds the producer up.
#include "inertial/runtime/slot_ring.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <chrono>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"

namespace inertial {
namespace {

TEST(SlotRing, RefusesWhenFullAndKeepsOrder) {
  SlotRing<int> ring(3, 0);
  EXPECT_EQ(ring.capacity(), 3u);
  for (int round = 0; round < 5; ++round) {  // across the wrap-around
    for (int i = 0; i < 3; ++i) {
      int* slot = ring.Claim();
      ASSERT_NE(slot, nullptr);
      *slot = 10 * round + i;
      ring.Commit();
    }
    EXPECT_EQ(ring.Claim(), nullptr);
    EXPECT_EQ(ring.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      const int* front = ring.Front();
      ASSERT_NE(front, nullptr);
      EXPECT_EQ(*front, 10 * round + i);
      ring.Pop();
    }
    EXPECT_EQ(ring.Front(), nullptr);
  }
  EXPECT_THROW(SlotRing<int>(0, 0), std::invalid_argument);
}

struct Slot {
  long sequence = 0;
  Eigen::VectorXd values;
};

#ifndef INERTIAL_ALLOCATIONS_NOT_COUNTED
TEST(SlotRing, FillingASlotOfThePrototypesSizesAllocatesNothing) {
  Slot prototype;
  prototype.values = Eigen::VectorXd::Zero(12);
  SlotRing<Slot> ring(8, prototype);
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(12, 0.0, 1.0);
  Doorbell bell;
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 1000; ++i) {
    Slot* s = ring.Claim();
    s->sequence = i;
    s->values = v;  // same size: Eigen copies into the slot's memory
    ring.Commit();
    bell.Ring();
    ring.Pop();
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
}
#endif

// One producer, one consumer: every item committed arrives, in order, with its contents.
TEST(SlotRing, PassesEveryItemInOrderBetweenTwoThreads) {
  Slot prototype;
  prototype.values = Eigen::VectorXd::Zero(4);
  SlotRing<Slot> ring(16, prototype);
  Doorbell bell;
  constexpr long kItems = 200000;
  long refused = 0;
  std::thread producer([&] {
    for (long i = 0; i < kItems;) {
      Slot* s = ring.Claim();
      if (s == nullptr) {
        ++refused;
        std::this_thread::yield();
        continue;
      }
      s->sequence = i;
      s->values.setConstant(static_cast<double>(i));
      ring.Commit();
      bell.Ring();
      ++i;
    }
  });
  long expected = 0;
  while (expected < kItems) {
    const Slot* s = ring.Front();
    if (s == nullptr) {
      bell.Wait(std::chrono::milliseconds(10));
      continue;
    }
    ASSERT_EQ(s->sequence, expected);
    ASSERT_EQ(s->values[3], static_cast<double>(expected));
    ring.Pop();
    ++expected;
  }
  producer.join();
  EXPECT_EQ(ring.Front(), nullptr);
}

// A consumer that sleeps 20 ms per item (a slow disk): the producer's 1000 hand-overs are not held
// up by it (each returns at once; what does not fit is refused and counted), and the consumer gets
// exactly the ones accepted.
TEST(SlotRing, ASleepingConsumerNeverHoldsTheProducerUp) {
  SlotRing<long> ring(4, 0);
  Doorbell bell;
  std::atomic<bool> done{false};
  long consumed = 0;
  std::thread consumer([&] {
    for (;;) {
      const bool finishing = done;
      bell.Wait(std::chrono::milliseconds(5));
      while (ring.Front() != nullptr) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ring.Pop();
        ++consumed;
      }
      if (finishing) return;
    }
  });
  long handed = 0, dropped = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long i = 0; i < 1000; ++i) {
    if (long* slot = ring.Claim()) {
      *slot = i;
      ring.Commit();
      bell.Ring();
      ++handed;
    } else {
      ++dropped;
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  done = true;
  bell.Ring();
  consumer.join();
  // Had the producer waited for the consumer, 1000 items would have taken 20 s; the bound is 1 s
  // (a loaded machine's scheduling), twenty times below.
  EXPECT_LT(seconds, 1.0);
  EXPECT_EQ(handed + dropped, 1000);
  EXPECT_GT(dropped, 0);
  EXPECT_EQ(consumed, handed);
}

TEST(Doorbell, WaitsUntilRungOrTheTimeout) {
  Doorbell bell;
  EXPECT_FALSE(bell.Wait(std::chrono::milliseconds(5)));
  bell.Ring();
  bell.Ring();
  EXPECT_TRUE(bell.Wait(std::chrono::milliseconds(5000)));
  EXPECT_FALSE(bell.Wait(std::chrono::milliseconds(5)));  // the second ring was absorbed by the first wake
  std::thread ringer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    bell.Ring();
  });
  EXPECT_TRUE(bell.Wait(std::chrono::milliseconds(5000)));
  ringer.join();
}

}  // namespace
}  // namespace inertial
