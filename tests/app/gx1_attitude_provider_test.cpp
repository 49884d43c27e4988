// Gx1AttitudeProvider on the in-process 3DM-GX1 emulator (a real pty): it opens, streams
// into the history a frame's time is looked up in, says where its newest sample is (what
// `ccdlane record` waits on), hands its event lines to the given sink, and names the
// configuration key when the device is not there.
// (The session cannot follow an in-process emulator's new pty after a hang-up, there
// being no link; reconnecting is the session's own tests' business.)
#include "app/gx1_attitude_provider.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "base/clock.hpp"

namespace ccdlane {
namespace {

struct Lines {
  std::mutex mutex;
  std::vector<std::pair<LogLevel, std::string>> got;
  LogSink sink() {
    return [this](LogLevel level, const char*, const char* line) {
      std::lock_guard<std::mutex> lock(mutex);
      got.emplace_back(level, line);
    };
  }
};

TEST(Gx1AttitudeProvider, EmulatedStreamsTheScriptedAttitudeAtAFramesTime) {
  gx1::EmulatorOptions emulator;
  emulator.attitude = [](double) { return Gx1Angles{2.5, -1.25, 40.0}; };
  Lines lines;
  Gx1AttitudeProvider provider(std::move(emulator), lines.sink());
  EXPECT_FALSE(provider.newest_sample_ns()) << "nothing before open";
  EXPECT_FALSE(provider.attitude_at(monotonic_ns()));
  ASSERT_EQ(provider.open(), "");
  std::atomic<bool> stop{false};
  std::thread gyro([&] { provider.run(stop); });

  const std::int64_t give_up = monotonic_ns() + 5'000'000'000;
  std::int64_t frame_ns = 0;
  while (monotonic_ns() < give_up) {
    const auto newest = provider.newest_sample_ns();
    if (newest && frame_ns == 0) frame_ns = *newest + 1'000'000;  // a frame just after the first sample
    if (newest && frame_ns != 0 && *newest > frame_ns) break;     // and a sample after it
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const std::optional<Gx1Angles> at = provider.attitude_at(frame_ns);
  const GyroState state = provider.state();
  const GyroCounters counters = provider.counters();
  // A hang-up: the session says so (notice), the emulator says where it is back (info).
  ASSERT_NE(provider.emulator(), nullptr);
  provider.emulator()->hang_up(20);
  bool session_line = false, emulator_line = false;
  for (const std::int64_t until = monotonic_ns() + 3'000'000'000;
       monotonic_ns() < until && !(session_line && emulator_line);
       std::this_thread::sleep_for(std::chrono::milliseconds(5))) {
    std::lock_guard<std::mutex> lock(lines.mutex);
    for (const auto& [level, text] : lines.got) {
      session_line |= level == LogLevel::notice;
      emulator_line |= level == LogLevel::info && text.rfind("gx1-emulator: ", 0) == 0;
    }
  }
  stop.store(true);
  gyro.join();
  provider.close();

  ASSERT_NE(frame_ns, 0) << "no sample within 5 s";
  ASSERT_TRUE(at.has_value());
  // The packet carries the angles as 16-bit counts of 360/65536 degrees.
  constexpr double kCount = 360.0 / 65536.0;
  EXPECT_NEAR(at->roll_deg, 2.5, kCount);
  EXPECT_NEAR(at->pitch_deg, -1.25, kCount);
  EXPECT_NEAR(at->yaw_deg, 40.0, kCount);
  EXPECT_EQ(state, GyroState::ok);
  EXPECT_GE(counters.samples, 2u);
  EXPECT_NE(provider.describe().find("3dm-gx1:emulated"), std::string::npos) << provider.describe();
  EXPECT_TRUE(session_line) << "the session's events reach the sink";
  EXPECT_TRUE(emulator_line) << "the emulator's lines reach the sink, marked as its own";
}

TEST(Gx1AttitudeProvider, AMissingDeviceNamesTheKeyAndThePath) {
  Lines lines;
  Gx1AttitudeProvider provider("/nonexistent/ttyUSB9", lines.sink());
  EXPECT_EQ(provider.open(), "gyro.device: \"/nonexistent/ttyUSB9\": /nonexistent/ttyUSB9: No such file or directory");
  EXPECT_FALSE(provider.newest_sample_ns());
  EXPECT_FALSE(provider.attitude_at(monotonic_ns()));
  // Absent at start: lost, with the cause as its problem, while the gyro thread retries.
  EXPECT_EQ(provider.state(), GyroState::lost);
  char problem[256];
  provider.last_problem(problem, sizeof problem);
  EXPECT_EQ(std::string(problem).rfind("absent: ", 0), 0u) << problem;
}

}  // namespace
}  // namespace ccdlane
