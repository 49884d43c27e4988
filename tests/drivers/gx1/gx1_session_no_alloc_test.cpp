// Proves "no allocation after open": a counting operator new watches the gyro thread
// while it streams, queries the history, loses the device and reopens it.
#include <atomic>
#include <string>

#include <gtest/gtest.h>

#include "drivers/device_state.hpp"
#include "drivers/gx1/gx1_emulator.hpp"
#include "drivers/gx1/gx1_session.hpp"
#include "tests/drivers/gx1/emulated_gx1.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane::gx1 {
namespace {

using test::kMs;

TEST(Gx1SessionNoAlloc, StreamingQueryingAndReopeningAllocateNothing) {
  const std::string link = test::test_link("no-alloc");
  EmulatorOptions eo;
  eo.link = link;
  eo.rate_hz = 200.0;
  eo.faults.garbage_every = 10;
  eo.faults.flip_every = 13;
  eo.faults.split_every = 3;
  Gx1Emulator emu(eo);
  ASSERT_EQ(emu.start(), 0);

  std::atomic<int> log_lines{0};  // a sink that does not allocate itself
  Gx1Session session(link, test::quick_session(), [&log_lines](LogLevel, const char*, const char*) { ++log_lines; });
  ASSERT_EQ(session.open(), 0);  // may allocate; nothing after it may

  std::size_t allocated = 0;
  int queries_ok = 0;
  bool hung_up = false;
  {
    const ccdlane::test::AllocationScope guard;  // this (the gyro) thread only
    const std::int64_t end = monotonic_ns() + 1500 * kMs;
    while (monotonic_ns() < end) {
      session.poll_once(20);
      if (session.attitude_at(monotonic_ns()).status == AttitudeStatus::ok) ++queries_ok;
      if (!hung_up && session.counters().samples > 50) {
        emu.hang_up(200);  // the emulator thread allocates as it likes; it is not counted
        hung_up = true;
      }
    }
    allocated = guard.count();
  }
  const SessionCounters c = session.counters();
  EXPECT_EQ(allocated, 0u);
  EXPECT_EQ(c.reopens, 1u) << "the reopen path was exercised";
  EXPECT_GT(c.bad_checksums, 0u) << "the resync path was exercised";
  EXPECT_GT(c.samples, 150u);
  EXPECT_GT(queries_ok, 10);
  EXPECT_GE(log_lines.load(), 2);
}

TEST(Gx1SessionNoAlloc, TheCounterWorks) {
  const ccdlane::test::AllocationScope guard;
  void* p = ::operator new(16);  // a call, not a new-expression: the compiler may not elide it
  ::operator delete(p);
  EXPECT_EQ(guard.count(), 1u);
}

}  // namespace
}  // namespace ccdlane::gx1
