// The "say once, carry on" policy lives here so that every thread applies the same rules.
#include "daemon/realtime.hpp"

#include <pthread.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "base/log.hpp"

namespace ccdlane {
namespace {

int sys_lock_all_memory() { return ::mlockall(MCL_CURRENT | MCL_FUTURE) == 0 ? 0 : -errno; }
int sys_unlock_all_memory() { return ::munlockall() == 0 ? 0 : -errno; }
int sys_set_fifo_priority(int priority) {
  sched_param p{};
  p.sched_priority = priority;
  return -::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &p);  // returns an errno value
}
int sys_set_affinity(const cpu_set_t& cpus) { return -::pthread_setaffinity_np(::pthread_self(), sizeof cpus, &cpus); }

constexpr RealtimeSyscalls kSystemCalls{sys_lock_all_memory, sys_unlock_all_memory, sys_set_fifo_priority,
                                        sys_set_affinity};

// "0,1,3" into out.
void format_cpus(const std::vector<int>& cpus, char* out, std::size_t size) {
  std::size_t used = 0;
  out[0] = '\0';
  for (std::size_t i = 0; i < cpus.size() && used + 1 < size; ++i) {
    const int n = std::snprintf(out + used, size - used, i == 0 ? "%d" : ",%d", cpus[i]);
    if (n < 0) break;
    used += static_cast<std::size_t>(n);
  }
}

}  // namespace

const RealtimeSyscalls& system_realtime_syscalls() { return kSystemCalls; }

RealtimeSetup::RealtimeSetup(const RealtimeConfig& config, const RealtimeSyscalls& calls)
    : config_(config), calls_(calls) {
  CPU_ZERO(&cpus_);
  for (int cpu : config_.cpus) CPU_SET(cpu, &cpus_);  // 0..1023, checked at config load
}

bool RealtimeSetup::lock_memory() {
  if (!config_.mlock) return false;
  const int r = calls_.lock_all_memory();
  if (r == 0) {
    memory_locked_.store(true, std::memory_order_relaxed);
    log_line(LogLevel::info, "realtime", "memory locked (mlockall)");
    return true;
  }
  // A partly successful mlockall may leave MCL_FUTURE in force; undo it so a later
  // allocation cannot fail on the lock limit.
  calls_.unlock_all_memory();
  refusals_.fetch_add(1, std::memory_order_relaxed);
  if (first_time(said_mlock_))
    log_line(LogLevel::warning, "realtime",
             "cannot lock memory (mlockall: %s); running without it (needs CAP_IPC_LOCK or a large enough "
             "LimitMEMLOCK)",
             std::strerror(-r));
  return false;
}

bool RealtimeSetup::apply_to_current_thread(const char* thread, int priority) {
  bool all = true;
  if (priority > 0) {
    const int r = calls_.set_fifo_priority(priority);
    if (r == 0) {
      fifo_threads_.fetch_add(1, std::memory_order_relaxed);
      log_line(LogLevel::info, "realtime", "%s thread: SCHED_FIFO priority %d", thread, priority);
    } else {
      all = false;
      refusals_.fetch_add(1, std::memory_order_relaxed);
      if (first_time(said_fifo_))
        log_line(LogLevel::warning, "realtime",
                 "SCHED_FIFO priority %d for the %s thread refused (%s); threads run with normal scheduling "
                 "(needs CAP_SYS_NICE or an RLIMIT_RTPRIO)",
                 priority, thread, std::strerror(-r));
    }
  }
  if (!config_.cpus.empty()) {
    const int r = calls_.set_affinity(cpus_);
    char list[128];
    format_cpus(config_.cpus, list, sizeof list);
    if (r == 0) {
      log_line(LogLevel::info, "realtime", "%s thread: on cpus %s", thread, list);
    } else {
      all = false;
      refusals_.fetch_add(1, std::memory_order_relaxed);
      if (first_time(said_affinity_))
        log_line(LogLevel::warning, "realtime", "cannot keep the %s thread on cpus %s (%s); threads run on any CPU",
                 thread, list, std::strerror(-r));
    }
  }
  return all;
}

void RealtimeSetup::describe(char* out, std::size_t size) const {
  char list[128];
  format_cpus(config_.cpus, list, sizeof list);
  std::snprintf(out, size, "mlock %s, SCHED_FIFO on %d thread(s), cpus %s", memory_locked() ? "on" : "off",
                fifo_threads(), config_.cpus.empty() ? "any" : list);
}

}  // namespace ccdlane
