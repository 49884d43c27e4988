// The daemon's vehicle inputs through a real LCM bus (memq://): a gateway publishes
// vehicle_state_t, ccdlaned's bus thread hands it to the vehicle state listener, and the
// pipeline's lane estimator (rendered drive frames, live-camera style: no recorded
// vehicle values) warns of a drift to the right without the indicator, stays silent
// with the right indicator on; once the gateway has been silent for longer than the
// maximum age, or while it sends only states beyond physical bounds, LDW is unavailable
// (vehicle_fault) and no warning is given on the garbage.
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>

#include "base/clock.hpp"
#include "bus/channels.hpp"
#include "bus/vehicle_state_listener.hpp"
#include "core/evaluation/ldw_scenarios.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/vehicle_drive.hpp"
#include "daemon/bus_thread.hpp"
#include "daemon/frame_processor.hpp"
#include "daemon/pipeline.hpp"
#include "tests/core/synth/rendered_road.hpp"

namespace ccdlane {
namespace {

constexpr std::int64_t kMaxAgeNs = 500'000'000;  // as ccdlaned's

// What the pipeline published for one frame.
struct Seen {
  std::uint64_t frame = 0;
  bool ok = false;
  ldw::Side fired = ldw::Side::none;
  double speed_mps = 0.0;
  ldw::TurnIndicator indicator = ldw::TurnIndicator::none;
  ldw::Availability reason = ldw::Availability::none;
};

class SeenSink : public LaneSink {
 public:
  explicit SeenSink(std::size_t capacity) : seen_(capacity) {}
  bool publish_lane(const LaneEstimate& e, std::int64_t, std::int64_t) override {
    const std::uint64_t n = count_.load(std::memory_order_relaxed);
    if (n >= seen_.size()) return false;
    seen_[n] = Seen{e.frame, e.ok, e.ldw.fired, e.ldw.speed_mps, e.ldw.indicator, e.ldw.reason};
    count_.store(n + 1, std::memory_order_release);
    return true;
  }
  std::uint64_t count() const { return count_.load(std::memory_order_acquire); }
  std::vector<Seen> seen() const { return {seen_.begin(), seen_.begin() + static_cast<long>(count())}; }

 private:
  std::vector<Seen> seen_;
  std::atomic<std::uint64_t> count_{0};
};

// The drive's frames as a live camera gives them (the drive's own time as the recorded
// time, its gyro reading, no vehicle values), frame k only once frame k-1 was published
// (nothing is dropped, whatever the load), and the gateway called before each.
class DriveSource : public FrameSource {
 public:
  using Gateway = std::function<void(const VehicleFrame&)>;
  DriveSource(const Config& c, const VehicleDrive& drive, const SeenSink& sink, Gateway gateway)
      : config_(c), drive_(drive), renderer_(c.camera, c.synth), sink_(sink), gateway_(std::move(gateway)) {}
  std::string open() override { return ""; }
  int width() const override { return config_.camera.Nu; }
  int height() const override { return config_.camera.Nv; }
  PixelFormat format() const override { return PixelFormat::mono8; }
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    if (next_ >= drive_.num_frames()) return CaptureStatus::end_of_stream;
    const std::int64_t deadline = monotonic_ns() + timeout_ms * 1'000'000LL;
    while (sink_.count() < next_) {
      if (monotonic_ns() > deadline) return CaptureStatus::timeout;
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    const SynthFrame f = drive_.synth_frame(next_, config_.nominal_pose(), config_.synth.gyro_noise_deg);
    renderer_.render(f, into);
    gateway_(drive_.frame(next_));
    meta = FrameMeta{};
    meta.sequence = next_++;
    meta.t_ns = monotonic_ns();
    meta.recorded_t_ns = f.t_ns;
    meta.gyro = f.gyro;
    return CaptureStatus::frame;
  }
  void close() override {}
  std::string describe() const override { return "rendered drive"; }
  std::string last_problem() const override { return ""; }
  SourceCounters counters() const override { return {}; }

 private:
  const Config& config_;
  const VehicleDrive& drive_;
  RoadRenderer renderer_;
  const SeenSink& sink_;
  Gateway gateway_;
  std::uint64_t next_ = 0;
};

// The CAN gateway's side of the bus: publishes and waits until the daemon's bus thread
// has taken the message, so that the frame after it is estimated with it.
class Gateway {
 public:
  Gateway(lcm_t* lcm, const VehicleStateListener& listener) : lcm_(lcm), listener_(listener) {}
  void publish(double speed_mps, std::optional<double> yaw_rate, std::int8_t indicator) const {
    vehicle_state_t m{};
    m.utime = realtime_us();
    m.speed_mps = speed_mps;
    m.has_yaw_rate = yaw_rate.has_value();
    m.yaw_rate_radps = yaw_rate.value_or(0.0);
    m.turn_indicator = indicator;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    const std::uint64_t before = listener_.received() + listener_.rejected();
    const std::string channel = channel_name("CCDLANE_", Channel::vehicle);
    ASSERT_EQ(lcm_publish(lcm_, channel.c_str(), bytes.data(), static_cast<unsigned>(bytes.size())), 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (listener_.received() + listener_.rejected() == before && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    ASSERT_GT(listener_.received() + listener_.rejected(), before) << "the bus thread took or refused the message";
  }

 private:
  lcm_t* lcm_;
  const VehicleStateListener& listener_;
};

// The daemon's wiring on an in-process bus: the listener on the vehicle channel, the bus
// thread handling it, the pipeline taking each frame's inputs from the listener.
std::vector<Seen> run_drive(const ldw::ScenarioSpec& spec,
                            const std::function<void(const Gateway&, const VehicleFrame&)>& gateway) {
  const Config c = test::scenario_config(spec);
  const VehicleDrive drive(spec.drive, spec.vehicle);
  lcm_t* lcm = lcm_create("memq://");
  EXPECT_NE(lcm, nullptr);
  std::vector<Seen> seen;
  {
    VehicleStateListener listener(lcm, channel_name("CCDLANE_", Channel::vehicle));
    BusThread bus(lcm);
    const Gateway gw(lcm, listener);
    SeenSink sink(drive.num_frames());
    DriveSource source(c, drive, sink, [&](const VehicleFrame& truth) { gateway(gw, truth); });
    EstimatorProcessor processor(c, source);
    RealtimeConfig realtime_config;
    RealtimeSetup realtime(realtime_config);
    Pipeline pipeline(source, nullptr, processor, sink, realtime, PipelineOptions{});
    pipeline.set_vehicle_state(&listener, kMaxAgeNs);
    bus.start();
    pipeline.start();
    pipeline.run();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
    while (!pipeline.finished() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(pipeline.finished()) << "the drive was processed within 300 s";
    pipeline.stop();
    bus.stop();
    seen = sink.seen();
  }
  lcm_destroy(lcm);
  return seen;
}

// The rendered 0.5 m/s drift to the right, shortened as in lane_estimator_ldw_test.
ldw::ScenarioSpec drift_right() {
  ldw::ScenarioSpec spec = ldw::departure_scenario(0.5, ldw::Side::right, 0.0);
  spec.drive.duration_s -= spec.drive.drift_at_s - 3.0;
  spec.drive.drift_at_s = 3.0;
  return spec;
}

std::vector<Seen> warnings_in(const std::vector<Seen>& seen) {
  std::vector<Seen> w;
  for (const Seen& s : seen)
    if (s.fired != ldw::Side::none) w.push_back(s);
  return w;
}

TEST(VehicleInputsBus, ADriftToTheRightIsWarnedWithoutTheIndicator) {
  const ldw::ScenarioSpec spec = drift_right();
  const VehicleDrive drive(spec.drive, spec.vehicle);
  const std::vector<Seen> seen = run_drive(spec, [](const Gateway& gw, const VehicleFrame& truth) {
    gw.publish(truth.speed_mps, truth.measured_yaw_rate_radps, vehicle_state_t::TURN_INDICATOR_NONE);
  });
  ASSERT_EQ(seen.size(), drive.num_frames()) << "every frame processed";
  for (const Seen& s : seen) EXPECT_NEAR(s.speed_mps, drive.frame(s.frame).speed_mps, 1e-9) << "the bus's speed";
  const std::vector<Seen> w = warnings_in(seen);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].fired, ldw::Side::right);
  const ldw::LdwWarningConfig lines;
  const double dlc_mm = drive.frame(w[0].frame).wheel_dlc.right_m * 1e3;
  EXPECT_LE(dlc_mm, lines.earliest_warning_mm);
  EXPECT_GE(dlc_mm, lines.latest_warning_mm);
}

TEST(VehicleInputsBus, TheRightIndicatorOnTheBusSuppressesTheWarning) {
  const ldw::ScenarioSpec spec = drift_right();
  const std::vector<Seen> seen = run_drive(spec, [](const Gateway& gw, const VehicleFrame& truth) {
    gw.publish(truth.speed_mps, truth.measured_yaw_rate_radps, vehicle_state_t::TURN_INDICATOR_RIGHT);
  });
  ASSERT_FALSE(seen.empty());
  int ok = 0;
  for (const Seen& s : seen) {
    EXPECT_EQ(s.indicator, ldw::TurnIndicator::right) << "frame " << s.frame;
    ok += s.ok;
  }
  EXPECT_GT(ok, static_cast<int>(seen.size()) * 9 / 10) << "the lane was seen: the silence means something";
  EXPECT_TRUE(warnings_in(seen).empty());
}

TEST(VehicleInputsBus, AGatewayThatFellSilentIsAVehicleFault) {
  ldw::ScenarioSpec spec = drift_right();
  spec.drive.duration_s = 0.2;  // 7 frames at 30 Hz
  const double configured_mps = spec.vehicle.configured_speed_mps();
  const std::vector<Seen> seen = run_drive(spec, [](const Gateway& gw, const VehicleFrame& truth) {
    if (truth.index == 0) gw.publish(12.5, std::nullopt, vehicle_state_t::TURN_INDICATOR_LEFT);
    // The gateway falls silent; by frame 3 its last message is older than the maximum age.
    if (truth.index == 3) std::this_thread::sleep_for(std::chrono::nanoseconds(kMaxAgeNs + 200'000'000));
  });
  ASSERT_EQ(seen.size(), 7u);
  EXPECT_DOUBLE_EQ(seen[0].speed_mps, 12.5);
  EXPECT_EQ(seen[0].indicator, ldw::TurnIndicator::left);
  EXPECT_NE(seen[0].reason, ldw::Availability::vehicle_fault);
  for (std::size_t k = 3; k < seen.size(); ++k) {
    EXPECT_DOUBLE_EQ(seen[k].speed_mps, configured_mps) << "frame " << k << ": its last indicator does not hold";
    EXPECT_EQ(seen[k].indicator, ldw::TurnIndicator::none) << "frame " << k;
    EXPECT_EQ(seen[k].reason, ldw::Availability::vehicle_fault) << "frame " << k << ": not the configured speed";
  }
}

// 150 m/s once gave false warnings, 1e30 made every frame no_lane, a yaw rate of 1e30
// was used and an indicator of 99 taken: each is refused, and LDW says why it is off.
TEST(VehicleInputsBus, AGatewaySendingOnlyImpossibleStatesIsAVehicleFault) {
  ldw::ScenarioSpec spec = drift_right();
  const std::vector<Seen> seen = run_drive(spec, [](const Gateway& gw, const VehicleFrame& truth) {
    switch (truth.index % 4) {
      case 0: gw.publish(150.0, std::nullopt, vehicle_state_t::TURN_INDICATOR_NONE); break;
      case 1: gw.publish(1e30, std::nullopt, vehicle_state_t::TURN_INDICATOR_NONE); break;
      case 2: gw.publish(truth.speed_mps, 1e30, vehicle_state_t::TURN_INDICATOR_NONE); break;
      default: gw.publish(truth.speed_mps, std::nullopt, 99); break;
    }
  });
  ASSERT_FALSE(seen.empty());
  int ok = 0;
  for (const Seen& s : seen) {
    EXPECT_EQ(s.reason, ldw::Availability::vehicle_fault) << "frame " << s.frame;
    ok += s.ok;
  }
  EXPECT_GT(ok, static_cast<int>(seen.size()) * 9 / 10) << "the lanes are seen: only LDW is off";
  EXPECT_TRUE(warnings_in(seen).empty());
}

}  // namespace
}  // namespace ccdlane
