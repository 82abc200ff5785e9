#pragma once
// A "latest value" slot: the hand-over between threads that must never queue up latency.
// A producer publish()es; a newer value replaces an unread one, and each value replaced
// before any reader saw it is counted as a drop. Readers remember the sequence number of
// the last value they got and wait for a newer one, with a timeout, so a slow reader skips
// values instead of slowing the producer (docs/architecture.md "The running service").
//
// Used for the capture hand-over (T = a frame, moved through take_newer() by the one
// consumer) and for the encoded JPEG handed to the HTTP thread (T = a shared_ptr, copied by
// any number of readers through wait_newer()/try_newer()).
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stop_token>
#include <utility>

namespace probeless {

template <typename T>
class LatestFrame {
 public:
  // 0 = "nothing yet": a reader starts with 0 and the first value published has sequence 1.
  using Sequence = std::uint64_t;

  struct Item {
    Sequence sequence = 0;
    T value;
  };

  LatestFrame() = default;
  LatestFrame(const LatestFrame&) = delete;
  LatestFrame& operator=(const LatestFrame&) = delete;
  LatestFrame(LatestFrame&&) = delete;
  LatestFrame& operator=(LatestFrame&&) = delete;
  ~LatestFrame() = default;

  // Replaces the value and wakes every waiting reader. Returns the new sequence number.
  Sequence publish(T value) {
    Sequence seq;
    {
      std::lock_guard lock(mutex_);
      if (value_.has_value() && !read_) ++drops_;
      value_ = std::move(value);
      read_ = false;
      seq = ++sequence_;
    }
    changed_.notify_all();
    return seq;
  }

  // The value if it is newer than `after`, without waiting.
  std::optional<Item> try_newer(Sequence after) {
    std::lock_guard lock(mutex_);
    return copy_if_newer(after);
  }

  // Waits up to `timeout` for a value newer than `after`. nullopt on timeout, and once the
  // slot is closed and holds nothing newer (a newer value is still handed out after close).
  template <typename Rep, typename Period>
  std::optional<Item> wait_newer(Sequence after, std::chrono::duration<Rep, Period> timeout) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return has_newer(after) || closed_; });
    return copy_if_newer(after);
  }

  // As wait_newer(), also returning early when `stop` is requested.
  template <typename Rep, typename Period>
  std::optional<Item> wait_newer(Sequence after, std::chrono::duration<Rep, Period> timeout,
                                 std::stop_token stop) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, stop, timeout, [&] { return has_newer(after) || closed_; });
    return copy_if_newer(after);
  }

  // As wait_newer(), but moves the value out (no copy of a large frame). For a slot with a
  // single consumer: the slot is empty afterwards until the next publish().
  template <typename Rep, typename Period>
  std::optional<Item> take_newer(Sequence after, std::chrono::duration<Rep, Period> timeout) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return has_newer(after) || closed_; });
    if (!has_newer(after)) return std::nullopt;
    read_ = true;
    Item item{sequence_, std::move(*value_)};
    value_.reset();
    return item;
  }

  // The current value whatever its age (nullopt before the first publish or after a take),
  // without counting it as read: for a look that must not hide drops (status, snapshots).
  std::optional<Item> peek() const {
    std::lock_guard lock(mutex_);
    if (!value_.has_value()) return std::nullopt;
    return Item{sequence_, *value_};
  }

  // Wakes every waiter for good: used at shutdown so that consumer threads can be joined.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    changed_.notify_all();
  }

  bool closed() const {
    std::lock_guard lock(mutex_);
    return closed_;
  }
  // Sequence number of the newest value (= values published so far).
  Sequence sequence() const {
    std::lock_guard lock(mutex_);
    return sequence_;
  }
  // Values replaced before any reader got them.
  std::uint64_t drops() const {
    std::lock_guard lock(mutex_);
    return drops_;
  }

 private:
  bool has_newer(Sequence after) const { return value_.has_value() && sequence_ > after; }

  std::optional<Item> copy_if_newer(Sequence after) {
    if (!has_newer(after)) return std::nullopt;
    read_ = true;
    return Item{sequence_, *value_};
  }

  mutable std::mutex mutex_;
  std::condition_variable_any changed_;
  std::optional<T> value_;
  Sequence sequence_ = 0;
  bool read_ = false;
  bool closed_ = false;
  std::uint64_t drops_ = 0;
};

}  // namespace probeless
