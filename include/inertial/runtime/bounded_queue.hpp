/// @file bounded_queue.hpp
/// A fixed-capacity queue between one producer thread (the LCM receiver) and one consumer (the
/// estimator): its slots are allocated once, a push into a full queue fails (the caller counts
/// the drop) instead of growing memory, and a pop waits at most a timeout.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <vector>

namespace inertial {

template <typename T>
class BoundedQueue {
 public:
  /// @param prototype copied into every slot (so that slots hold their memory from the start).
  BoundedQueue(std::size_t capacity, const T& prototype) : slots_(capacity, prototype) {}

  /// Copies `item` in; false (nothing changed) if the queue is full.
  bool TryPush(const T& item) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (size_ == slots_.size()) return false;
      slots_[(head_ + size_) % slots_.size()] = item;
      ++size_;
    }
    ready_.notify_one();
    return true;
  }

  /// Copies the oldest item into *out and removes it; false if none arrived within `timeout`.
  bool PopWait(T* out, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!ready_.wait_for(lock, timeout, [this] { return size_ > 0; })) return false;
    *out = slots_[head_];
    head_ = (head_ + 1) % slots_.size();
    --size_;
    return true;
  }

  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return size_;
  }
  std::size_t capacity() const { return slots_.size(); }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::vector<T> slots_;
  std::size_t head_ = 0, size_ = 0;
};

}  // namespace inertial
