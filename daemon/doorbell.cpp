// FUTEX_WAIT compares the word with `seen` inside the kernel before sleeping: that
// comparison is what makes the look-then-sleep race harmless.
#include "daemon/doorbell.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>

namespace ccdlane {
namespace {

// std::atomic<uint32_t> is a plain 32-bit word on Linux, which is what the futex wants.
std::uint32_t* word(const std::atomic<std::uint32_t>& a) {
  return reinterpret_cast<std::uint32_t*>(const_cast<std::atomic<std::uint32_t>*>(&a));
}

}  // namespace

void Doorbell::ring() {
  count_.fetch_add(1, std::memory_order_release);
  syscall(SYS_futex, word(count_), FUTEX_WAKE_PRIVATE, 0x7fffffff, nullptr, nullptr, 0);
}

void Doorbell::wait(std::uint32_t seen, int timeout_ms) const {
  if (count_.load(std::memory_order_acquire) != seen) return;
  timespec timeout{};
  timeout.tv_sec = timeout_ms / 1000;
  timeout.tv_nsec = static_cast<long>(timeout_ms % 1000) * 1'000'000;
  syscall(SYS_futex, word(count_), FUTEX_WAIT_PRIVATE, seen, &timeout, nullptr, 0);
}

}  // namespace ccdlane
