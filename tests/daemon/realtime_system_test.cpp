// Real-time set-up with the real system calls: as root the settings take effect; as an
// unprivileged user they are refused, said once, and the process carries on.
#include <fcntl.h>
#include <pthread.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "base/log.hpp"
#include "daemon/realtime.hpp"
#include "tests/support/as_user.hpp"
#include "tests/support/count_of.hpp"

namespace ccdlane {
namespace {

// The real system calls, as root: the calling thread really runs SCHED_FIFO on CPU 0.
TEST(RealtimeSetupSystem, AsRootTheSettingsTakeEffect) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer turns mlockall into a no-op";
#endif
  if (geteuid() != 0) GTEST_SKIP() << "needs root";
  RealtimeConfig config;
  config.mlock = true;
  config.cpus = {0};
  RealtimeSetup rt(config);
  std::thread t([&] {
    EXPECT_TRUE(rt.apply_to_current_thread("test", 10));
    int policy = 0;
    sched_param p{};
    pthread_getschedparam(pthread_self(), &policy, &p);
    EXPECT_EQ(policy, SCHED_FIFO);
    EXPECT_EQ(p.sched_priority, 10);
    cpu_set_t cpus;
    pthread_getaffinity_np(pthread_self(), sizeof cpus, &cpus);
    EXPECT_EQ(CPU_COUNT(&cpus), 1);
    EXPECT_TRUE(CPU_ISSET(0, &cpus));
  });
  t.join();
  EXPECT_TRUE(rt.lock_memory());
  munlockall();
}

// The real system calls as "nobody" with no lockable memory: refused, said once, and the
// process goes on (it is a forked child so the test process keeps its privileges).
TEST(RealtimeSetupSystem, AsAnUnprivilegedUserItDegrades) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer turns mlockall into a no-op that succeeds";
#endif
  if (geteuid() != 0) GTEST_SKIP() << "needs root to become nobody";
  const test::ChildRun child = test::run_as_user(
      test::kNobody,
      [] {
        const rlimit none{0, 0};
        return setrlimit(RLIMIT_MEMLOCK, &none) == 0 && setrlimit(RLIMIT_RTPRIO, &none) == 0;
      },
      [](int fd) {
        set_log_output(fd, false);
        RealtimeConfig config;
        config.mlock = true;
        RealtimeSetup rt(config);
        const bool locked = rt.lock_memory();
        const bool fifo1 = rt.apply_to_current_thread("capture", 20);
        const bool fifo2 = rt.apply_to_current_thread("processing", 20);
        void* still_works = malloc(64 << 20);  // no MCL_FUTURE left behind to make this fail
        return !locked && !fifo1 && !fifo2 && still_works != nullptr && rt.refusals() == 3 ? 0 : 12;
      });
  const std::string& text = child.out;
  EXPECT_TRUE(child.exited_with(0)) << child.status << ": " << text;
  EXPECT_EQ(test::count_of(text, "\n"), 2) << text;
  EXPECT_EQ(test::count_of(text, "cannot lock memory (mlockall: "), 1) << text;
  EXPECT_EQ(test::count_of(text, "SCHED_FIFO priority 20 for the capture thread refused (Operation not permitted)"), 1)
      << text;
}

}  // namespace
}  // namespace ccdlane
