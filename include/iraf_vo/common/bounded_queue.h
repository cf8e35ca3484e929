// Bounded single-producer / single-consumer queue connecting pipeline threads. close() wakes both sides: push()
// then drops its item, pop() drains what is queued and then returns false.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>

namespace iraf_vo {

template <typename Item>
class BoundedQueue {
 public:
  explicit BoundedQueue(size_t capacity) : capacity_(capacity) {}

  void push(Item&& item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return queue_.size() < capacity_ || closed_; });
    if (closed_) return;
    queue_.push_back(std::move(item));
    not_empty_.notify_one();
  }

  /// false once closed and empty.
  bool pop(Item* item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return !queue_.empty() || closed_; });
    if (queue_.empty()) return false;
    *item = std::move(queue_.front());
    queue_.pop_front();
    not_full_.notify_one();
    return true;
  }

  void close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    not_full_.notify_all();
    not_empty_.notify_all();
  }

 private:
  size_t capacity_;
  bool closed_ = false;
  std::deque<Item> queue_;
  std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
};

}  // namespace iraf_vo
