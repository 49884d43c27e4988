// The session as the daemon drives it: a gyro thread in poll_once(), a processing
// thread asking attitude_at() and the counters, the emulator in its own thread. Run
// under ThreadSanitizer in CI.
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "drivers/device_state.hpp"
#include "drivers/gx1/gx1_emulator.hpp"
#include "drivers/gx1/gx1_session.hpp"
#include "tests/drivers/gx1/emulated_gx1.hpp"

namespace ccdlane::gx1 {
namespace {

using test::kMs;

TEST(Gx1SessionThreads, GyroThreadWritesWhileTheProcessingThreadReads) {
  const std::string link = test::test_link("threads");
  EmulatorOptions eo;
  eo.link = link;
  eo.rate_hz = 200.0;
  eo.attitude = [](double t) { return Gx1Angles{10.0, -5.0, std::remainder(170.0 + 90.0 * t, 360.0)}; };
  Gx1Emulator emu(eo);
  ASSERT_EQ(emu.start(), 0);
  Gx1Session session(link, test::quick_session(), [](LogLevel, const char*, const char*) {});
  ASSERT_EQ(session.open(), 0);

  std::atomic<bool> stop{false};
  std::thread gyro([&] {
    while (!stop) session.poll_once(10);
  });
  int ok = 0, bad = 0;
  const std::int64_t end = monotonic_ns() + 1200 * kMs;
  bool hung_up = false;
  while (monotonic_ns() < end) {
    const AttitudeQuery q = session.attitude_at(monotonic_ns() - 5 * kMs);  // a frame 5 ms old
    if (q.status == AttitudeStatus::ok) {
      ++ok;
      // Roll and pitch are constant in the script: any mixing of samples would show.
      if (q.angles.roll_deg != degrees_from_counts(counts_from_degrees(10.0)) ||
          q.angles.pitch_deg != degrees_from_counts(counts_from_degrees(-5.0)))
        ++bad;
    }
    (void)session.counters();
    (void)session.state();
    if (!hung_up && monotonic_ns() > end - 700 * kMs) {
      emu.hang_up(100);
      hung_up = true;
    }
    sleep_until(monotonic_ns() + 2 * kMs);
  }
  stop = true;
  gyro.join();
  EXPECT_GT(ok, 100);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(session.counters().reopens, 1u);
}

}  // namespace
}  // namespace ccdlane::gx1
