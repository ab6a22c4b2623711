/// @file slot_ring.hpp
/// The hand-over from inertiald's real-time threads (the estimator, the receiver) to its sink
/// threads, in the shape of realtime_tools' RealtimePublisher: the real-time side only fills a
/// slot and hands it over; another thread does the I/O.
/// - SlotRing: a fixed ring of slots between one producer thread and one consumer thread. The
///   slots are made once from a prototype (so that a producer that writes into a slot of the same
///   sizes allocates nothing); Claim never waits: a full ring answers null and the producer counts
///   the item as dropped. Lock-free: two atomic indices, no mutex, no system call.
/// - Doorbell: wakes the consumer. Ring() is sem_post (never blocks, allocates nothing, safe even
///   in a signal handler); Wait() sleeps until rung or a timeout.
#pragma once

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <ctime>
#include <stdexcept>
#include <vector>

#include <semaphore.h>

namespace inertial {

template <typename T>
class SlotRing {
 public:
  /// `capacity` slots, each a copy of `prototype`. @throws std::invalid_argument if capacity is 0.
  SlotRing(std::size_t capacity, const T& prototype) : slots_(capacity + 1, prototype) {
    if (capacity == 0) throw std::invalid_argument("SlotRing: capacity must be positive");
  }
  SlotRing(const SlotRing&) = delete;
  SlotRing& operator=(const SlotRing&) = delete;

  /// Producer: the next free slot to fill (its previous contents are stale), or null if the ring
  /// is full. The slot is handed over by Commit; claiming again without a Commit returns the same slot.
  T* Claim() {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    const std::size_t next = Next(tail);
    if (next == head_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[tail];
  }
  /// Producer: hands the slot of the last successful Claim over to the consumer.
  void Commit() { tail_.store(Next(tail_.load(std::memory_order_relaxed)), std::memory_order_release); }

  /// Consumer: the oldest slot handed over, or null if none.
  T* Front() {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[head];
  }
  /// Consumer: gives the slot of Front back to the producer.
  void Pop() { head_.store(Next(head_.load(std::memory_order_relaxed)), std::memory_order_release); }

  std::size_t capacity() const { return slots_.size() - 1; }
  /// Items handed over and not yet popped (exact from either thread's side, approximate from others).
  std::size_t size() const {
    const std::size_t head = head_.load(std::memory_order_acquire), tail = tail_.load(std::memory_order_acquire);
    return tail >= head ? tail - head : slots_.size() - head + tail;
  }

 private:
  std::size_t Next(std::size_t i) const { return i + 1 == slots_.size() ? 0 : i + 1; }

  std::vector<T> slots_;  // one more than the capacity: head == tail means empty
  alignas(64) std::atomic<std::size_t> head_{0};  // the consumer's
  alignas(64) std::atomic<std::size_t> tail_{0};  // the producer's
};

class Doorbell {
 public:
  Doorbell() {
    if (::sem_init(&sem_, 0, 0) != 0) throw std::runtime_error("Doorbell: sem_init failed");
  }
  ~Doorbell() { ::sem_destroy(&sem_); }
  Doorbell(const Doorbell&) = delete;
  Doorbell& operator=(const Doorbell&) = delete;

  /// Wakes the waiter (or the next Wait returns at once). Never blocks.
  void Ring() { ::sem_post(&sem_); }

  /// Sleeps until rung or `timeout` passed; true if rung. Rings that came meanwhile are absorbed:
  /// the waiter looks at everything after a wake, so one wake stands for all of them.
  bool Wait(std::chrono::milliseconds timeout) {
    timespec deadline{};
    ::clock_gettime(CLOCK_REALTIME, &deadline);
    const long long ns = static_cast<long long>(deadline.tv_nsec) + static_cast<long long>(timeout.count()) * 1000000LL;
    deadline.tv_sec += static_cast<time_t>(ns / 1000000000LL);
    deadline.tv_nsec = static_cast<long>(ns % 1000000000LL);
    int r;
    while ((r = ::sem_timedwait(&sem_, &deadline)) != 0 && errno == EINTR) {
    }
    if (r != 0) return false;
    while (::sem_trywait(&sem_) == 0) {
    }
    return true;
  }

 private:
  sem_t sem_;
};

}  // namespace inertial
