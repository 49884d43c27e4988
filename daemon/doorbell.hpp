// A futex doorbell: one thread sleeps until another rings. Ringing bumps a counter and
// the sleeper sleeps only while the counter still has the value it saw, so a ring that
// comes between its look and its sleep is never lost.
#pragma once

#include <atomic>
#include <cstdint>

namespace ccdlane {

// Unlike std::atomic::wait, the wait is bounded (a stop request is seen even if its ring
// were missed) and the implementation is the two system calls below, nothing hidden.
class Doorbell {
 public:
  // Read before looking for work; pass to wait().
  std::uint32_t value() const { return count_.load(std::memory_order_acquire); }
  // Wakes every sleeper. No allocation; one system call.
  void ring();
  // Sleeps while the count is still `seen`, at most timeout_ms (spurious returns are
  // possible: callers look again).
  void wait(std::uint32_t seen, int timeout_ms) const;

 private:
  std::atomic<std::uint32_t> count_{0};
  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t), "futex word");
};

}  // namespace ccdlane
