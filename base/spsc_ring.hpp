// A lock-free single-producer single-consumer ring of small values (frame buffer
// indices, latency samples), after rigtorp's SPSCQueue, plus drop-oldest for the camera.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <type_traits>

namespace ccdlane {

// Layout and ordering follow rigtorp/SPSCQueue: the two indices and each side's cached
// copy of the other's index live on their own cache lines, each side reads its own index
// relaxed and the peer's with acquire, and publishes with release; the peer's index is
// reloaded only when the ring looks full (producer) or empty (consumer). Capacity is
// fixed at construction, the only allocation.
//
// One deliberate difference: the camera must never wait for processing, and the frame
// it drops when processing falls behind should be the oldest, not the newest. So the
// producer may take the oldest entry out of a full ring (push_dropping_oldest). That
// makes the read index writable by both sides, so it moves by compare-and-swap, and the
// indices are 64-bit counters that never wrap (slot = counter % capacity): a consumer
// descheduled between reading a slot and claiming it could otherwise be fooled by an
// index that came round again (ABA). With counters, full and empty differ by value
// (write - read == capacity vs. 0), so the slack slot rigtorp needs is not needed.
template <typename T>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "the ring carries small values, not objects");
  static_assert(std::atomic<T>::is_always_lock_free, "slots must be lock-free atomics");

 public:
  explicit SpscRing(std::size_t capacity)
      : capacity_(capacity == 0 ? 1 : capacity),
        storage_(std::make_unique<std::atomic<T>[]>(capacity_ + 2 * kPadding)),
        slots_(storage_.get() + kPadding) {}
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  std::size_t capacity() const noexcept { return capacity_; }

  // Producer: appends `value` unless the ring is full.
  [[nodiscard]] bool try_push(T value) noexcept {
    const std::uint64_t w = write_.load(std::memory_order_relaxed);
    if (w - read_cache_ >= capacity_) {
      read_cache_ = read_.load(std::memory_order_acquire);
      if (w - read_cache_ >= capacity_) return false;
    }
    slots_[w % capacity_].store(value, std::memory_order_relaxed);
    write_.store(w + 1, std::memory_order_release);
    return true;
  }

  // Producer: appends `value`; if the ring is full, first takes out the oldest entry and
  // returns it (the producer owns it again, e.g. a frame buffer to capture into).
  [[nodiscard]] std::optional<T> push_dropping_oldest(T value) noexcept {
    if (try_push(value)) return std::nullopt;
    const std::uint64_t w = write_.load(std::memory_order_relaxed);
    std::uint64_t r = read_cache_;  // fresh: try_push just reloaded it
    for (;;) {
      if (w - r < capacity_) {  // the consumer made room meanwhile
        read_cache_ = r;
        append(w, value);
        return std::nullopt;
      }
      const T oldest = slots_[r % capacity_].load(std::memory_order_relaxed);
      // Races the consumer's claim of the same entry; exactly one of us gets it.
      if (read_.compare_exchange_weak(r, r + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
        read_cache_ = r + 1;
        append(w, value);
        return oldest;
      }
    }
  }

  // Consumer: takes the oldest entry, if any.
  [[nodiscard]] bool try_pop(T& out) noexcept {
    // acquire, not relaxed as in rigtorp: the producer may have moved the read index.
    std::uint64_t r = read_.load(std::memory_order_acquire);
    for (;;) {
      if (r >= write_cache_) {
        write_cache_ = write_.load(std::memory_order_acquire);
        if (r >= write_cache_) return false;
      }
      // A stale r (the producer dropped that entry meanwhile) may read a slot the producer
      // is rewriting; the slot is atomic and the claim below then fails, so the value is
      // never used.
      const T value = slots_[r % capacity_].load(std::memory_order_relaxed);
      if (read_.compare_exchange_weak(r, r + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
        out = value;
        return true;
      }
    }
  }

  // Entries waiting; exact only when neither side is active.
  std::size_t size_approx() const noexcept {
    const std::uint64_t r = read_.load(std::memory_order_acquire);
    const std::uint64_t w = write_.load(std::memory_order_acquire);
    return w > r ? static_cast<std::size_t>(w - r) : 0;
  }

 private:
  static constexpr std::size_t kCacheLine = 64;
  // Slots padded at both ends so neighbouring heap blocks never share their cache lines.
  static constexpr std::size_t kPadding = (kCacheLine - 1) / sizeof(std::atomic<T>) + 1;

  void append(std::uint64_t w, T value) noexcept {
    slots_[w % capacity_].store(value, std::memory_order_relaxed);
    write_.store(w + 1, std::memory_order_release);
  }

  const std::size_t capacity_;
  const std::unique_ptr<std::atomic<T>[]> storage_;
  std::atomic<T>* const slots_;

  alignas(kCacheLine) std::atomic<std::uint64_t> write_{0};  // pushes so far; producer's
  alignas(kCacheLine) std::uint64_t read_cache_ = 0;         // producer's copy of read_
  alignas(kCacheLine) std::atomic<std::uint64_t> read_{0};   // pops and drops so far
  alignas(kCacheLine) std::uint64_t write_cache_ = 0;        // consumer's copy of write_
  char tail_padding_[kCacheLine - sizeof(std::uint64_t)] = {};
};

}  // namespace ccdlane
