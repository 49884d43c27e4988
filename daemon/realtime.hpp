// Real-time set-up from [realtime]: locked memory, SCHED_FIFO priorities and CPU
// affinity per thread. Where the system refuses (no root, no capability), it says so
// once and the daemon runs without.
#pragma once

#include <sched.h>

#include <atomic>
#include <cstddef>

#include "app/config.hpp"

namespace ccdlane {

// The system calls involved, each returning 0 or -errno. Tests substitute them to play
// "not permitted" without changing users.
struct RealtimeSyscalls {
  int (*lock_all_memory)();                    // mlockall(MCL_CURRENT | MCL_FUTURE)
  int (*unlock_all_memory)();                  // munlockall()
  int (*set_fifo_priority)(int priority);      // SCHED_FIFO for the calling thread
  int (*set_affinity)(const cpu_set_t& cpus);  // CPU affinity of the calling thread
};
const RealtimeSyscalls& system_realtime_syscalls();

class RealtimeSetup {
 public:
  explicit RealtimeSetup(const RealtimeConfig& config, const RealtimeSyscalls& calls = system_realtime_syscalls());

  // [realtime] mlock: locks every page, present and future. Call once the fixed pool is
  // allocated and every thread exists: under a tight RLIMIT_MEMLOCK this call can then
  // only fail (reported, undone), never make a later allocation or thread creation fail.
  // Returns true when memory is locked (false also when not asked for).
  bool lock_memory();

  // For the calling thread: SCHED_FIFO at `priority` (0: keep normal scheduling) and the
  // [realtime] cpus (empty: any). Each kind of refusal is reported once per process.
  // Returns true when everything asked for took effect.
  bool apply_to_current_thread(const char* thread, int priority);

  bool memory_locked() const { return memory_locked_.load(std::memory_order_relaxed); }
  int fifo_threads() const { return fifo_threads_.load(std::memory_order_relaxed); }
  int refusals() const { return refusals_.load(std::memory_order_relaxed); }

  // "mlock on, SCHED_FIFO on 2 threads, cpus 0,1" for the start-up log.
  void describe(char* out, std::size_t size) const;

 private:
  const RealtimeConfig& config_;
  const RealtimeSyscalls& calls_;
  cpu_set_t cpus_;
  std::atomic<bool> memory_locked_{false};
  std::atomic<int> fifo_threads_{0};
  std::atomic<int> refusals_{0};
  std::atomic<bool> said_mlock_{false}, said_fifo_{false}, said_affinity_{false};
};

}  // namespace ccdlane
