// The factories: what each [source] kind and [gyro] device gives in this build, and a
// clear line for what it does not have.
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "app/frame_inputs.hpp"
#include "app/gyro_factory.hpp"
#include "app/source_factory.hpp"
#include "base/clock.hpp"
#include "core/synth/synth_drive.hpp"
#include "daemon/daemon.hpp"
#include "daemon/frame_processor.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

TEST(SourceFactory, SynthRendersTheConfiguredCameraAndFeedsTheEstimator) {
  Config c = default_config();
  c.synth.frames = 3;
  c.source.rate_hz = 0;  // unpaced
  auto source = make_frame_source(c);
  ASSERT_EQ(source->open(), "");
  EXPECT_EQ(source->width(), c.camera.Nu);
  EXPECT_EQ(source->height(), c.camera.Nv);
  EXPECT_EQ(source->format(), PixelFormat::mono8);
  EXPECT_EQ(source->describe(), "synth 800x600 mono8 0 fps (3 frames of a 3-lane road, looping)");
  EstimatorProcessor processor(c, *source);

  // Rendered once, replayed looping: frame 3 is frame 0 again, with its gyro reading.
  std::vector<std::uint8_t> a(static_cast<std::size_t>(c.camera.Nu * c.camera.Nv)), b(a.size());
  const MutableImageView va{a.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8};
  const MutableImageView vb{b.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8};
  FrameMeta m0, m;
  ASSERT_EQ(source->capture(va, m0, 100), CaptureStatus::frame);
  ASSERT_TRUE(m0.gyro.has_value());
  for (int i = 0; i < 3; ++i) ASSERT_EQ(source->capture(vb, m, 100), CaptureStatus::frame);
  EXPECT_EQ(m.sequence, 3u);
  EXPECT_EQ(a, b);
  EXPECT_EQ(m.gyro->roll_deg, m0.gyro->roll_deg);
  // Stamped with the drive's time, as `ccdlane synth` stamps its frames, going on past the loop.
  EXPECT_EQ(m0.frame_t_ns(), 0);
  EXPECT_EQ(m.frame_t_ns(), SynthDrive(c.synth, c.nominal_pose()).frame(3).t_ns);
  EXPECT_GT(m.frame_t_ns(), 0);

  // And the estimator finds the lane it shows.
  const ImageView frame0 = va;
  const LaneEstimate e = processor.process(frame_inputs(&frame0, 0, m0, {}, false));
  EXPECT_TRUE(e.ok);
}

TEST(SourceFactory, SynthFramesCarryNoGyroWhenAGyroDeviceIsConfigured) {
  Config c = default_config();
  c.synth.frames = 1;
  c.gyro.device = "emulated";
  auto source = make_frame_source(c);
  ASSERT_EQ(source->open(), "");
  std::vector<std::uint8_t> a(static_cast<std::size_t>(c.camera.Nu * c.camera.Nv));
  FrameMeta m;
  ASSERT_EQ(source->capture({a.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8}, m, 1000),
            CaptureStatus::frame);
  EXPECT_FALSE(m.gyro.has_value());
}

TEST(SourceFactory, EveryKindIsBuiltAndBadDevicesSayWhyOnOpen) {
  Config c = default_config();
  c.source.kind = SourceKind::frames;
  c.source.path = "/nonexistent/frames";
  auto frames = make_frame_source(c);
  const std::string why = frames->open();
  EXPECT_NE(why.find("/nonexistent/frames"), std::string::npos) << why;
  c.source.kind = SourceKind::video;
  c.source.path = "/nonexistent/drive.mp4";
  EXPECT_EQ(make_frame_source(c)->open(), "/nonexistent/drive.mp4: no such file");
  c.source.kind = SourceKind::v4l2;
  c.source.device = "/nonexistent/video9";
  auto v4l2 = make_frame_source(c);
  EXPECT_NE(v4l2->open().find("/nonexistent/video9"), std::string::npos);
  c.source.kind = SourceKind::aravis;
}

TEST(EstimatorProcessor, RefusesFramesOfAnotherSizeThanTheCamera) {
  Config c = default_config();
  c.synth.frames = 1;
  auto source = make_frame_source(c);
  ASSERT_EQ(source->open(), "");
  c.camera.Nu = 640;
  EXPECT_THROW(EstimatorProcessor(c, *source), std::runtime_error);
}

TEST(GyroFactory, NoDeviceMeansNoGyroAndEmulatedStreams) {
  Config c = default_config();
  EXPECT_EQ(make_attitude_provider(c), nullptr);
  c.gyro.device = "emulated";
  auto gyro = make_attitude_provider(c);
  ASSERT_NE(gyro, nullptr);
  ASSERT_EQ(gyro->open(), "");
  std::atomic<bool> stop{false};
  std::thread reader([&] { gyro->run(stop); });
  std::optional<Gx1Angles> a;
  for (int i = 0; i < 100 && !a; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    a = gyro->attitude_at(monotonic_ns());
  }
  EXPECT_EQ(gyro->state(), GyroState::ok);
  stop = true;
  reader.join();
  gyro->close();
  ASSERT_TRUE(a.has_value());
  // The emulator follows the synthetic drive: roll and pitch are the camera's mounting
  // attitude within the sway and bump amplitudes plus the gyro noise.
  EXPECT_NEAR(a->roll_deg, c.attitude.phi_deg, c.synth.roll_sway_deg + 4 * c.synth.gyro_noise_deg + 0.01);
  EXPECT_NEAR(a->pitch_deg, -c.attitude.theta_deg, c.synth.pitch_bump_deg + 4 * c.synth.gyro_noise_deg + 0.01);
  EXPECT_GT(gyro->counters().samples, 0u);
}

TEST(GyroFactory, AMissingDeviceIsOneLineOnOpen) {
  Config c = default_config();
  c.gyro.device = "/nonexistent/ttyUSB7";
  auto gyro = make_attitude_provider(c);
  const std::string why = gyro->open();
  EXPECT_EQ(why.find("gyro.device: \"/nonexistent/ttyUSB7\""), 0u) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos);
}

// Each way of pinning the roll makes an unobservable configuration acceptable: a gyro
// device, a roll prior, a lane-width prior, or the roll fixed.
void expect_each_remedy_accepted(const Config& c) {
  Config with_gyro = c;
  with_gyro.gyro.device = "/dev/ttyUSB0";
  EXPECT_EQ(daemon_config_problem(with_gyro), "");
  Config roll_prior = c;
  roll_prior.prior.phi_deg = Prior{0.0, 1.0};
  EXPECT_EQ(daemon_config_problem(roll_prior), "");
  Config width_prior = c;
  width_prior.prior.lane_width_mm = Prior{3600.0, 300.0};
  EXPECT_EQ(daemon_config_problem(width_prior), "");
  Config roll_fixed = c;
  roll_fixed.solver.free.remove(FreeParam::phi);
  EXPECT_EQ(daemon_config_problem(roll_fixed), "");
}

TEST(ConfigProblem, RollNeedsAGyroARollPriorOrALaneWidthPrior) {
  Config c = default_config();
  c.source.kind = SourceKind::v4l2;
  EXPECT_NE(daemon_config_problem(c).find("phi and y0 are free with no gyro"), std::string::npos);
  expect_each_remedy_accepted(c);
}

// A frame directory's gyro is its frames.csv columns: with them the roll is pinned, without
// them (and no gyro device, no prior) the configuration is refused naming the file.
TEST(ConfigProblem, AFrameDirectoryWithoutGyroColumnsCannotPinTheRoll) {
  Config c = default_config();
  c.source.kind = SourceKind::frames;
  test::TempDir with, without;
  with.write("frames.csv", "file,t_ns,roll_deg,pitch_deg,yaw_deg\n0.pgm,0,0.5,-3,0\n");
  without.write("frames.csv", "file,t_ns,truth_phi_deg\n0.pgm,0,0.5\n");
  c.source.path = with.path();
  EXPECT_EQ(frames_without_gyro(c), "");
  EXPECT_EQ(daemon_config_problem(c), "");

  c.source.path = without.path();
  EXPECT_EQ(frames_without_gyro(c),
            "source.path: " + without.file("frames.csv") + " has no gyro columns (roll_deg, pitch_deg)");
  EXPECT_EQ(daemon_config_problem(c),
            "source.path: " + without.file("frames.csv") +
                " has no gyro columns (roll_deg, pitch_deg) and there is no [gyro] device, no [prior] phi_deg and no "
                "[prior] lane_width_mm, while solver.free has phi and y0: the roll is not observable; add one of them "
                "or fix phi");
  expect_each_remedy_accepted(c);

  // A directory that cannot be read is not called gyro-less: opening it says what is wrong.
  c.source.path = without.file("missing");
  EXPECT_EQ(daemon_config_problem(c), "");
}

TEST(ConfigProblem, ScaleAndFocalLengthNeedPriorsEvenWithAGyro) {
  Config c = demo_config();
  c.solver.free.add(FreeParam::H);
  EXPECT_EQ(daemon_config_problem(c).rfind("solver.free: H is free without [prior] H_mm", 0), 0u);
  c.prior.H_mm = Prior{1400.0, 20.0};
  EXPECT_EQ(daemon_config_problem(c), "");
  c.solver.free.add(FreeParam::f);
  EXPECT_EQ(daemon_config_problem(c).rfind("solver.free: f is free without [prior] f_mm", 0), 0u);
}

TEST(DemoConfig, IsRunnable) {
  const Config c = demo_config();
  EXPECT_EQ(daemon_config_problem(c), "");
  EXPECT_EQ(c.source.kind, SourceKind::synth);
  EXPECT_EQ(c.source.rate_hz, 30.0);
  EXPECT_EQ(c.lcm.url, "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(c.gyro.device, "emulated");
}

}  // namespace
}  // namespace ccdlane
