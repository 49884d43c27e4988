// Gx1AttitudeProvider on the in-process 3DM-GX1 emulator (a real pty): it opens, streams
// into the history a frame's time is looked up in, says where its newest sample is (what
// `ccdlane record` waits on), hands its event lines to the given sink, and names the
// configuration key when the device is not there; readings no vehicle can have are
// refused, counted and make it a faulty gyro.
// (The session cannot follow an in-process emulator's new pty after a hang-up, there
// being no link; reconnecting is the session's own tests' business.)
#include "app/gx1_attitude_provider.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <numbers>
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

// Streaming 0x31, the provider gives the vehicle's yaw rate (+ left) from the sensor's
// rates: the scripted heading turning clockwise at 15 degrees/s is -15 degrees/s. A 0x0E
// stream has no rate to give.
TEST(Gx1AttitudeProvider, TheYawRateOfA0x31StreamIsTheVehiclesTurnToTheLeft) {
  for (const std::uint8_t stream : {gx1::cmd::stab_euler_vectors, gx1::cmd::stab_euler}) {
    gx1::EmulatorOptions emulator;
    emulator.attitude = [](double t_s) { return Gx1Angles{1.5, -3.0, std::remainder(100.0 + 15.0 * t_s, 360.0)}; };
    gx1::SessionOptions options;
    options.stream_command = stream;
    Gx1AttitudeProvider provider(std::move(emulator), {}, options);
    EXPECT_FALSE(provider.yaw_rate_at(monotonic_ns())) << "nothing before open";
    ASSERT_EQ(provider.open(), "");
    std::atomic<bool> stop{false};
    std::thread gyro([&] { provider.run(stop); });
    std::optional<std::int64_t> newest;
    for (const std::int64_t give_up = monotonic_ns() + 5'000'000'000;
         monotonic_ns() < give_up && !(newest = provider.newest_sample_ns());)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const std::optional<double> rate = newest ? provider.yaw_rate_at(*newest) : std::nullopt;
    stop.store(true);
    gyro.join();
    provider.close();
    ASSERT_TRUE(newest) << "no sample within 5 s";
    if (stream == gx1::cmd::stab_euler) {
      EXPECT_FALSE(rate) << "0x0E carries no rate";
      continue;
    }
    ASSERT_TRUE(rate);
    // Counts of 1 / 3855 rad/s (the default gain 8500): two of them make the yaw rate.
    EXPECT_NEAR(*rate, -15.0 * std::numbers::pi / 180.0, 2.0 * 8500.0 / 32768000.0 / std::cos(0.06));
  }
}

// A pitch of 170 or a roll of 175 degrees once made every frame fail too_few_marks while
// the status said "gyro ok": now the gyro is stale, with the cause as its problem.
TEST(Gx1AttitudeProvider, AnglesNoVehicleCanHaveAreRefusedAndMakeTheGyroStale) {
  for (const Gx1Angles impossible : {Gx1Angles{0.5, 170.0, 10.0}, Gx1Angles{175.0, -2.0, 10.0}}) {
    gx1::EmulatorOptions emulator;
    emulator.attitude = [impossible](double) { return impossible; };
    Lines lines;
    Gx1AttitudeProvider provider(std::move(emulator), lines.sink());
    ASSERT_EQ(provider.open(), "");
    std::atomic<bool> stop{false};
    std::thread gyro([&] { provider.run(stop); });
    for (const std::int64_t give_up = monotonic_ns() + 5'000'000'000;
         monotonic_ns() < give_up && provider.counters().refused < 20;)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const GyroState state = provider.state();
    const GyroCounters counters = provider.counters();
    const bool attitude = provider.attitude_at(monotonic_ns()).has_value();
    char problem[256];
    provider.last_problem(problem, sizeof problem);
    stop.store(true);
    gyro.join();
    provider.close();
    EXPECT_GE(counters.refused, 20u);
    EXPECT_EQ(counters.samples, 0u) << "none taken";
    EXPECT_FALSE(attitude);
    EXPECT_NE(state, GyroState::ok);
    EXPECT_NE(std::string(problem).find(impossible.pitch_deg > 90 ? "whose pitch" : "whose roll"), std::string::npos)
        << problem;
    int refusal_lines = 0;
    for (const auto& [level, text] : lines.got) refusal_lines += text.find("refused a reading") != std::string::npos;
    EXPECT_EQ(refusal_lines, 1) << "said once";
  }
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

// A regular file named as the device: a configuration error (the daemon does not start),
// not an absence to retry, and nothing written into it.
TEST(Gx1AttitudeProvider, ARegularFileIsNoDevice) {
  const std::string file = testing::TempDir() + "/gyro-" + std::to_string(::getpid()) + ".toml";
  std::FILE* f = std::fopen(file.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fclose(f);
  Gx1AttitudeProvider provider(file, {});
  EXPECT_EQ(provider.open(),
            "gyro.device: \"" + file + "\": " + file + ": not a character device (a serial port or a pty): refused");
  EXPECT_NE(provider.state(), GyroState::lost) << "not retried as an absent device";
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_size, 0) << "nothing written";
  ::unlink(file.c_str());
}

}  // namespace
}  // namespace ccdlane
