// Real-time set-up: refused calls are reported once and the daemon carries on (with an
// injected EPERM, and for real as an unprivileged user); as root the settings take.
#include "daemon/realtime.hpp"

#include <fcntl.h>
#include <grp.h>
#include <pthread.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "base/log.hpp"
#include "tests/support/log_capture.hpp"

namespace ccdlane {
namespace {

// The fake kernel: what each call returns, and how often it was made.
struct FakeKernel {
  int lock_result = 0, fifo_result = 0, affinity_result = 0;
  int lock_calls = 0, unlock_calls = 0, fifo_calls = 0, affinity_calls = 0;
  int last_priority = 0;
  cpu_set_t last_cpus{};
};
FakeKernel g_fake;

const RealtimeSyscalls kFakeCalls{
    [] {
      ++g_fake.lock_calls;
      return g_fake.lock_result;
    },
    [] {
      ++g_fake.unlock_calls;
      return 0;
    },
    [](int priority) {
      ++g_fake.fifo_calls;
      g_fake.last_priority = priority;
      return g_fake.fifo_result;
    },
    [](const cpu_set_t& cpus) {
      ++g_fake.affinity_calls;
      g_fake.last_cpus = cpus;
      return g_fake.affinity_result;
    },
};

using test::count_of;
using test::LogCapture;

TEST(RealtimeSetup, NothingAskedNothingDone) {
  g_fake = {};
  RealtimeConfig config;  // mlock off, priority 0, any cpu
  RealtimeSetup rt(config, kFakeCalls);
  EXPECT_FALSE(rt.lock_memory());
  EXPECT_TRUE(rt.apply_to_current_thread("capture", 0));
  EXPECT_EQ(g_fake.lock_calls + g_fake.fifo_calls + g_fake.affinity_calls, 0);
}

TEST(RealtimeSetup, GrantedSettingsAreAppliedAndCounted) {
  g_fake = {};
  RealtimeConfig config;
  config.mlock = true;
  config.cpus = {1, 3};
  RealtimeSetup rt(config, kFakeCalls);
  LogCapture log;
  EXPECT_TRUE(rt.lock_memory());
  EXPECT_TRUE(rt.apply_to_current_thread("capture", 50));
  EXPECT_TRUE(rt.apply_to_current_thread("processing", 40));
  EXPECT_EQ(g_fake.last_priority, 40);
  EXPECT_TRUE(CPU_ISSET(1, &g_fake.last_cpus));
  EXPECT_TRUE(CPU_ISSET(3, &g_fake.last_cpus));
  EXPECT_FALSE(CPU_ISSET(0, &g_fake.last_cpus));
  EXPECT_EQ(CPU_COUNT(&g_fake.last_cpus), 2);
  EXPECT_TRUE(rt.memory_locked());
  EXPECT_EQ(rt.fifo_threads(), 2);
  EXPECT_EQ(rt.refusals(), 0);
  char text[160];
  rt.describe(text, sizeof text);
  EXPECT_STREQ(text, "mlock on, SCHED_FIFO on 2 thread(s), cpus 1,3");
  EXPECT_EQ(count_of(log.text(), "warning"), 0);
}

TEST(RealtimeSetup, RefusalsAreReportedOnceAndEverythingElseGoesOn) {
  g_fake = {};
  g_fake.lock_result = -EPERM;
  g_fake.fifo_result = -EPERM;
  g_fake.affinity_result = -EINVAL;
  RealtimeConfig config;
  config.mlock = true;
  config.cpus = {0};
  RealtimeSetup rt(config, kFakeCalls);
  LogCapture log;
  EXPECT_FALSE(rt.lock_memory());
  EXPECT_EQ(g_fake.unlock_calls, 1);  // a refused mlockall leaves no MCL_FUTURE behind
  for (const char* thread : {"capture", "processing", "gyro"}) EXPECT_FALSE(rt.apply_to_current_thread(thread, 30));
  EXPECT_EQ(g_fake.fifo_calls, 3);  // every thread tries...
  EXPECT_EQ(g_fake.affinity_calls, 3);
  EXPECT_EQ(rt.refusals(), 7);
  EXPECT_EQ(rt.fifo_threads(), 0);
  const std::string text = log.text();  // ...but each refusal is told once
  EXPECT_EQ(count_of(text, "\n"), 3) << text;
  EXPECT_EQ(count_of(text, "cannot lock memory (mlockall: Operation not permitted)"), 1) << text;
  EXPECT_EQ(count_of(text, "SCHED_FIFO priority 30 for the capture thread refused (Operation not permitted)"), 1)
      << text;
  EXPECT_EQ(count_of(text, "cannot keep the capture thread on cpus 0 (Invalid argument)"), 1) << text;
}

}  // namespace
}  // namespace ccdlane
