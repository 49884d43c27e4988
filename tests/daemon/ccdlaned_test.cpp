// ccdlaned as systemd runs it: a test-owned NOTIFY_SOCKET sees READY, WATCHDOG, STATUS
// and STOPPING; SIGTERM ends it cleanly within a second; SIGHUP is refused with one
// line; lane and status messages arrive on a real multicast bus; without privileges the
// real-time settings are refused once and it runs anyway; bad configurations are
// refused with one line and exit status 2.
#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "tests/daemon/child_process.hpp"
#include "tests/daemon/notify_socket.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/count_of.hpp"
#include "tests/support/run_process.hpp"
#include "tests/support/test_video.hpp"

namespace ccdlane {
namespace {

using Clock = std::chrono::steady_clock;

const std::string kDaemon = CCDLANE_DAEMON;

// The reference camera on a short synthetic drive (10 frames, rendered at start, looping).
std::string config_text(const std::string& url, double rate_hz, const std::string& extra = "") {
  return "[synth]\nframes = 10\n[source]\nkind = \"synth\"\nrate_hz = " + std::to_string(rate_hz) +
         "\n[lcm]\nurl = \"" + url + "\"\n" + extra;
}

int count_equal(const std::vector<std::string>& v, const std::string& what) {
  return static_cast<int>(std::count(v.begin(), v.end(), what));
}

// SIGTERM, then the messages the daemon sent until it exited, which must be with status 0
// within 2 s.
bool stops_cleanly(test::ChildProcess& child, lcm::LCM& bus) {
  child.signal(SIGTERM);
  const auto exit_status = child.wait_exit(2000);
  while (bus.handleTimeout(100) > 0) {
  }
  EXPECT_TRUE(exit_status.has_value()) << "still running 2 s after SIGTERM";
  return exit_status && WIFEXITED(*exit_status) && WEXITSTATUS(*exit_status) == 0;
}

// The daemon under a systemd-like supervisor: its notifications land on `socket`.
struct Supervised {
  Supervised(const test::TempDir& dir, const std::string& config_path, std::optional<uid_t> user = {})
      : socket(dir.file("notify")),
        stderr_path(dir.file("stderr")),
        child({kDaemon, "--config", config_path},
              test::ChildOptions{{"NOTIFY_SOCKET=" + socket.path(), "WATCHDOG_USEC=300000"}, "", stderr_path, user}) {}
  // SIGTERM as systemd sends it: the notifications up to STOPPING=1 (read before
  // reaping, as systemd does), then the exit. Expects exit status 0 within 2 s.
  struct Stop {
    std::vector<std::string> notifications;
    Clock::duration took;
  };
  Stop terminate() {
    const auto before = Clock::now();
    child.signal(SIGTERM);
    Stop stop{socket.receive_until("STOPPING=1", 1000), {}};
    const std::optional<int> exit_status = child.wait_exit(2000);
    stop.took = Clock::now() - before;
    EXPECT_TRUE(exit_status.has_value()) << "still running 2 s after SIGTERM";
    if (exit_status) {
      EXPECT_TRUE(WIFEXITED(*exit_status));
      EXPECT_EQ(WEXITSTATUS(*exit_status), 0);
    }
    return stop;
  }

  test::NotifySocket socket;
  std::string stderr_path;
  test::ChildProcess child;
};

TEST(Ccdlaned, NotifiesSystemdAndStopsCleanlyWithinASecondOfSigterm) {
  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml", config_text("memq://", 100));
  Supervised d(dir, config);

  std::vector<std::string> got = d.socket.receive_until("READY=1", 10000);
  ASSERT_EQ(got.back(), "READY=1") << test::read_file(d.stderr_path);
  for (const auto& m : d.socket.receive_until("never", 1500)) got.push_back(m);
  EXPECT_GE(count_equal(got, "WATCHDOG=1"), 3) << "pings every 100 ms while frames flow";
  const auto status =
      std::find_if(got.begin(), got.end(), [](const std::string& m) { return m.rfind("STATUS=", 0) == 0; });
  ASSERT_NE(status, got.end());
  EXPECT_EQ(status->rfind("STATUS=streaming ", 0), 0u) << *status;
  EXPECT_NE(status->find(", 0 allocations"), std::string::npos) << *status;

  const Supervised::Stop stop = d.terminate();
  ASSERT_FALSE(stop.notifications.empty());
  EXPECT_EQ(stop.notifications.back(), "STOPPING=1");
  EXPECT_LT(stop.took, std::chrono::seconds(1)) << "a requirement: clean shutdown within a second";
  const std::string log = test::read_file(d.stderr_path);
  EXPECT_EQ(test::count_of(log, "SIGTERM: stopping"), 1) << log;
  EXPECT_EQ(test::count_of(log, "0 allocations after ready"), 1) << log;
  // The stop line accounts for every frame: in = processed + dropped + left queued.
  long long in = -1, processed = -1, dropped = -1, queued = -1;
  const std::size_t at = log.rfind("stop: ");  // the last stop line: the totals
  ASSERT_NE(at, std::string::npos) << log;
  ASSERT_EQ(std::sscanf(log.c_str() + at, "stop: %lld frames in, %lld processed, %lld dropped, %lld left queued", &in,
                        &processed, &dropped, &queued),
            4)
      << log.substr(at);
  EXPECT_GT(in, 0);
  EXPECT_EQ(in, processed + dropped + queued) << log.substr(at);
}

// A missing camera under systemd: the reason goes to STATUS= and the exit waits out a
// pause (the unit restarts it for ever, StartLimitIntervalSec=0), which SIGTERM ends.
TEST(Ccdlaned, AFailedStartUnderSystemdSaysWhyAndPausesBeforeItsRestart) {
  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml",
                                       "[source]\nkind = \"v4l2\"\ndevice = \"/dev/video-none\"\n[prior]\nphi_deg = "
                                       "[0.0, 1.0]\n[lcm]\nurl = \"memq://\"\n");
  Supervised d(dir, config);
  std::optional<std::string> status;
  for (const auto end = Clock::now() + std::chrono::seconds(10); Clock::now() < end;)
    if ((status = d.socket.receive(200)) && status->rfind("STATUS=", 0) == 0) break;
  ASSERT_TRUE(status.has_value()) << test::read_file(d.stderr_path);
  EXPECT_EQ(status->rfind("STATUS=failed to start (camera): ", 0), 0u) << *status;
  EXPECT_NE(status->find("/dev/video-none"), std::string::npos) << *status;
  EXPECT_NE(status->find("; restarting in 5 s"), std::string::npos) << *status;
  EXPECT_FALSE(d.child.wait_exit(500).has_value()) << "pausing before the restart";
  d.child.signal(SIGTERM);
  const std::optional<int> exit_status = d.child.wait_exit(1000);
  ASSERT_TRUE(exit_status.has_value()) << "SIGTERM ends the pause";
  EXPECT_EQ(WEXITSTATUS(*exit_status), 1);
}

TEST(Ccdlaned, SighupIsRefusedWithOneLineAndTheDaemonGoesOn) {
  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml", config_text("memq://", 100));
  Supervised d(dir, config);
  ASSERT_EQ(d.socket.receive_until("READY=1", 10000).back(), "READY=1");
  d.child.signal(SIGHUP);
  d.socket.receive_until("never", 300);
  const auto after = d.socket.receive_until("never", 500);
  EXPECT_GE(count_equal(after, "WATCHDOG=1"), 2) << "still processing after SIGHUP";
  d.terminate();
  const std::string log = test::read_file(d.stderr_path);
  EXPECT_EQ(
      test::count_of(log, "SIGHUP: reloading the configuration is not supported; restart ccdlaned to apply changes"), 1)
      << log;
}

TEST(Ccdlaned, WithoutPrivilegesRealtimeIsRefusedOnceAndItRunsAnyway) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer turns mlockall into a no-op that succeeds";
#endif
  test::TempDir dir;
  chmod(dir.path().c_str(), 0777);  // nobody reads the config and writes its log here
  const std::string config = dir.write(
      "ccdlane.toml",
      config_text("memq://", 100, "[realtime]\nmlock = true\ncapture_priority = 50\nprocessing_priority = 40\n"));
  chmod(config.c_str(), 0644);
  Supervised d(dir, config, /*nobody*/ 65534);
  chmod(d.socket.path().c_str(), 0777);  // nobody may send to it
  ASSERT_EQ(d.socket.receive_until("READY=1", 10000).back(), "READY=1") << test::read_file(d.stderr_path);
  d.terminate();
  const std::string log = test::read_file(d.stderr_path);
  EXPECT_EQ(test::count_of(log, "warning: cannot lock memory (mlockall: "), 1) << log;
  EXPECT_EQ(test::count_of(log, "warning: SCHED_FIFO priority"), 1) << log;  // two threads refused, said once
  EXPECT_EQ(test::count_of(log, "mlock off, SCHED_FIFO on 0 thread(s)"), 1) << log;
}

// One lane message per processed frame, in order, and status once a second, on a real
// multicast bus in a private network namespace.
TEST(CcdlanedBus, PublishesLanesAndStatusOnUdpm) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";
  lcm::LCM bus(url);
  ASSERT_TRUE(bus.good());
  struct Got {
    std::vector<lane_estimate_t> lanes;
    std::vector<status_t> statuses;
  } got;
  // Functions, not member functions: see lcm_round_trip.cpp (UBSan false positive).
  bus.subscribeFunction(
      "CCDLANE_LANES",
      +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, Got* g) { g->lanes.push_back(*m); },
      &got);
  bus.subscribeFunction(
      "CCDLANE_STATUS",
      +[](const lcm::ReceiveBuffer*, const std::string&, const status_t* m, Got* g) { g->statuses.push_back(*m); },
      &got);

  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml", config_text(url, 50));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  const auto end = Clock::now() + std::chrono::seconds(15);
  while (got.statuses.size() < 3 && Clock::now() < end) bus.handleTimeout(200);
  ASSERT_TRUE(stops_cleanly(child, bus));

  ASSERT_GE(got.statuses.size(), 3u) << test::read_file(dir.file("stderr"));
  ASSERT_GE(got.lanes.size(), 50u);
  for (std::size_t i = 1; i < got.lanes.size(); ++i) {
    ASSERT_GT(got.lanes[i].frame, got.lanes[i - 1].frame) << "in order";
    EXPECT_GE(got.lanes[i].publish_utime, got.lanes[i].capture_utime);
  }
  for (const auto& m : got.lanes) EXPECT_TRUE(m.ok) << "frame " << m.frame << ": no lane estimate";
  const status_t& last = got.statuses.back();  // the final one, sent after the pipeline stopped
  EXPECT_EQ(last.ready, 1);
  EXPECT_EQ(last.allocations_since_ready, 0);
  EXPECT_LE(last.frames_processed_total + last.frames_dropped_total, last.frames_in_total);  // some may still be queued
  EXPECT_EQ(static_cast<std::size_t>(last.frames_processed_total), got.lanes.size()) << "one message per frame";
  EXPECT_EQ(last.camera.rfind("synth 800x600 mono8 50 fps", 0), 0u) << last.camera;
  // A full period in the middle of the run counts its frames (about 50; how many depends
  // on the machine's load, which is a benchmark's business, not this test's).
  EXPECT_GT(got.statuses[1].frames_processed, 0);
  EXPECT_LE(got.statuses[1].frames_processed, got.statuses[1].frames_in + 4);  // + what was queued before
  EXPECT_EQ(got.statuses[1].gyro_state, status_t::GYRO_NONE);
}

TEST(CcdlanedCommand, CheckConfigAcceptsAUsableFile) {
  test::TempDir dir;
  const std::string config = dir.write("ok.toml", config_text("memq://", 30));
  const auto r = test::run_process({kDaemon, "--check-config", "--config", config});
  EXPECT_EQ(r.exit_status, 0) << r.err;
  EXPECT_EQ(r.out, config + ": configuration ok\n");
  EXPECT_EQ(r.err, "");
}

TEST(CcdlanedCommand, BadConfigurationsAreOneLineAndExitTwo) {
  test::TempDir dir;
  const std::string bad_value = dir.write("bad.toml", "[daemon]\nqueue_depth = 0\n");
  auto r = test::run_process({kDaemon, "--check-config", "--config", bad_value});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlaned: " + bad_value + ":2: daemon.queue_depth: must be between 1 and 62 frames\n");

  // A camera without a gyro and the default free set (phi, y0): the roll is not observable.
  const std::string ill_posed = dir.write("v4l2.toml", "[source]\nkind = \"v4l2\"\n");
  r = test::run_process({kDaemon, "--config", ill_posed});  // refused before opening anything
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlaned: " + ill_posed +
                       ": solver.free: phi and y0 are free with no gyro ([gyro] device), no [prior] phi_deg and no "
                       "[prior] lane_width_mm: the roll is not observable; add one of them or fix phi\n");

  const std::string garbage = dir.write("garbage.toml", "[gyro]\nsigma_deg = \"lots\"\n");
  r = test::run_process({kDaemon, "--config", garbage});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(test::count_of(r.err, "\n"), 1) << r.err;
  EXPECT_EQ(r.err.rfind("ccdlaned: " + garbage + ":2: gyro.sigma_deg: ", 0), 0u) << r.err;

  r = test::run_process({kDaemon, "--config", dir.file("missing.toml")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlaned: " + dir.file("missing.toml") +
                       ": cannot read the configuration file: No such file or directory\n");

  r = test::run_process({kDaemon, "--frobnicate"});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(test::count_of(r.err, "\n"), 1) << r.err;
}

// Frames recorded without a gyro, no gyro device, phi and y0 free: refused before anything
// is opened, by the daemon and by --check-config alike, with the file named.
// 8192x8192 colour with queue_depth 62 once passed --check-config and died of a bare
// std::bad_alloc at start: refused at --check-config, here on a 4 GB address space.
TEST(CcdlanedCommand, AConfigurationNeedingMoreMemoryThanTheMachineIsRefused) {
  test::TempDir dir;
  const std::string config = dir.write("huge.toml",
                                       "[camera]\nNu = 8192\nNv = 8192\nUc_mm = 0.0005\nVc_mm = 0.0005\nk_px2 = "
                                       "0.0\n[source]\nkind = \"v4l2\"\npixel_format = "
                                       "\"colour\"\n[daemon]\nqueue_depth = 62\n[prior]\nphi_deg = [0.0, 1.0]\n");
  const auto r = test::run_process(
      {"/bin/sh", "-c", "ulimit -v 4194304; exec \"$@\"", "sh", kDaemon, "--check-config", "--config", config});
  EXPECT_EQ(r.exit_status, 2) << r.err;
  EXPECT_NE(r.err.find(config + ": needs an estimated 12800 MB at start"), std::string::npos) << r.err;
}

TEST(CcdlanedCommand, AFrameDirectoryWithoutGyroColumnsIsRefusedWhenTheRollNeedsOne) {
  test::TempDir dir;
  const std::string frames = dir.path() + "/frames";
  ASSERT_EQ(mkdir(frames.c_str(), 0755), 0);
  dir.write("frames/frames.csv", "file,t_ns\n000000.pgm,0\n000001.pgm,33333333\n");
  const std::string config =
      dir.write("frames.toml", "[source]\nkind = \"frames\"\npath = \"" + frames + "\"\n[lcm]\nurl = \"memq://\"\n");
  const std::string expected = "ccdlaned: " + config + ": source.path: " + frames +
                               "/frames.csv has no gyro columns (roll_deg, pitch_deg) and there is no [gyro] device, "
                               "no [prior] phi_deg and no [prior] lane_width_mm, while solver.free has phi and y0: the "
                               "roll is not observable; add one of them or fix phi\n";
  for (const bool check_only : {false, true}) {
    std::vector<std::string> argv = {kDaemon, "--config", config};
    if (check_only) argv.push_back("--check-config");
    const auto r = test::run_process(argv);
    EXPECT_EQ(r.exit_status, 2) << (check_only ? "--check-config" : "start");
    EXPECT_EQ(r.err, expected);
    EXPECT_EQ(r.out, "");
  }
  // The same directory with a roll prior is usable (as far as the configuration goes).
  const std::string with_prior = dir.write(
      "prior.toml", "[source]\nkind = \"frames\"\npath = \"" + frames + "\"\n[prior]\nphi_deg = [0.0, 1.0]\n");
  const auto ok = test::run_process({kDaemon, "--check-config", "--config", with_prior});
  EXPECT_EQ(ok.exit_status, 0) << ok.err;
}

TEST(CcdlanedCommand, AnUnusableBusFailsToStartNamingIt) {
  test::TempDir dir;
  const std::string config = dir.write("bus.toml", config_text("udpm://300.1.2.3:7667", 30));
  const auto r = test::run_process({kDaemon, "--config", config});
  EXPECT_EQ(r.exit_status, 1);
  // liblcm prints its own reason first ("Bad multicast IP address"); ours is the last line.
  const std::string ours = "ccdlaned: start: error: lcm: cannot open the bus \"udpm://300.1.2.3:7667\" ([lcm] url)\n";
  ASSERT_GE(r.err.size(), ours.size()) << r.err;
  EXPECT_EQ(r.err.substr(r.err.size() - ours.size()), ours);

  const std::string unknown = dir.write("unknown.toml", config_text("nosuchprovider://x", 30));
  const auto u = test::run_process({kDaemon, "--config", unknown});
  EXPECT_EQ(u.exit_status, 2) << "an unknown provider is a configuration error";
  EXPECT_EQ(test::count_of(u.err, "\n"), 1) << u.err;
}

TEST(CcdlanedCommand, WithoutAnyConfigurationTheBuiltInDemoIsChecked) {
  struct stat st {};
  if (stat("/etc/ccdlane/ccdlane.toml", &st) == 0) GTEST_SKIP() << "/etc/ccdlane/ccdlane.toml exists here";
  const auto r = test::run_process({kDaemon, "--check-config"});
  EXPECT_EQ(r.exit_status, 0) << r.err;
  EXPECT_EQ(r.out, "the built-in demo: configuration ok\n");
}

// Lanes and status as a subscriber on the private bus sees them.
struct BusCapture {
  explicit BusCapture(lcm::LCM& bus) {
    bus.subscribeFunction(
        "CCDLANE_LANES",
        +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, BusCapture* g) {
          g->lanes.push_back(*m);
        },
        this);
    bus.subscribeFunction(
        "CCDLANE_STATUS",
        +[](const lcm::ReceiveBuffer*, const std::string&, const status_t* m, BusCapture* g) {
          g->statuses.push_back(*m);
        },
        this);
  }
  std::vector<lane_estimate_t> lanes;
  std::vector<status_t> statuses;
};

// A gyro absent at start degrades the daemon instead of ending it: lanes go out, each
// saying that the roll is not observable (the default solver has phi and y0 free, no
// prior), the status says the gyro is lost and why, and the device keeps being tried.
TEST(CcdlanedBus, AnAbsentGyroAtStartDegradesAndSaysSoPerMessage) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  BusCapture got(bus);
  test::TempDir dir;
  const std::string config =
      dir.write("ccdlane.toml", config_text(test::kBusUrl, 30, "[gyro]\ndevice = \"/dev/ttyNONEXISTENT\"\n"));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  const auto end = Clock::now() + std::chrono::seconds(15);
  while (got.statuses.size() < 7 && Clock::now() < end) bus.handleTimeout(200);
  EXPECT_FALSE(child.wait_exit(0).has_value()) << "still running 7 s in: " << test::read_file(dir.file("stderr"));
  child.signal(SIGTERM);
  const auto exit_status = child.wait_exit(2000);
  ASSERT_TRUE(exit_status.has_value());
  EXPECT_EQ(WEXITSTATUS(*exit_status), 0);
  const std::string log = test::read_file(dir.file("stderr"));
  ASSERT_GE(got.statuses.size(), 7u) << log;
  ASSERT_GE(got.lanes.size(), 30u) << log;
  for (const auto& m : got.lanes) EXPECT_EQ(m.roll_unobservable, 1) << "frame " << m.frame;
  const status_t& s = got.statuses[got.statuses.size() - 2];
  EXPECT_EQ(s.gyro_state, status_t::GYRO_LOST);
  EXPECT_EQ(s.gyro_problem.rfind("absent: ", 0), 0u) << s.gyro_problem;
  EXPECT_NE(s.gyro_problem.find("/dev/ttyNONEXISTENT"), std::string::npos) << s.gyro_problem;
  EXPECT_EQ(test::count_of(log, "gyro: warning: absent: "), 1) << "said once, not at every retry: " << log;
}

// SIGTERM while the synthetic drive is still being rendered (120 frames: seconds of
// work): the daemon stops within about a second, not after the rendering.
TEST(Ccdlaned, SigtermDuringStartUpStopsWithinASecond) {
  test::TempDir dir;
  const std::string config = dir.write(
      "ccdlane.toml", "[synth]\nframes = 120\n[source]\nkind = \"synth\"\nrate_hz = 30\n[lcm]\nurl = \"memq://\"\n");
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const auto before = Clock::now();
  child.signal(SIGTERM);
  const std::optional<int> exit_status = child.wait_exit(5000);
  const auto took = Clock::now() - before;
  ASSERT_TRUE(exit_status.has_value());
  EXPECT_TRUE(WIFEXITED(*exit_status));
  EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << test::read_file(dir.file("stderr"));
  EXPECT_LT(took, std::chrono::milliseconds(1200)) << test::read_file(dir.file("stderr"));
}

// A recorded drive as the camera ([source] kind = "video"): one lane message per frame of
// the file, stamped with the file's own times, at the file's rate (not faster), through
// the same pipeline and status, and the end of the file ends the run.
TEST(CcdlanedBus, AVideoSourcePlaysAtTheFilesRate) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  BusCapture got(bus);
  test::TempDir dir;
  constexpr int kFrames = 30;  // 1.2 s at 25 fps
  std::vector<std::int64_t> times;
  for (int i = 0; i < kFrames; ++i) times.push_back(i * 40'000'000LL);
  const std::string video = test::write_test_video(dir.file("drive.mp4"), 800, 600, times);  // the default camera
  const std::string config =
      dir.write("video.toml", "[source]\nkind = \"video\"\npath = \"" + video +
                                  "\"\n[prior]\nphi_deg = [0.0, 1.0]\n[lcm]\nurl = \"" + test::kBusUrl + "\"\n");
  const auto start = Clock::now();
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  std::optional<int> exit_status;
  for (const auto end = start + std::chrono::seconds(20); !exit_status && Clock::now() < end;) {
    bus.handleTimeout(50);
    exit_status = child.wait_exit(0);
  }
  const auto took = Clock::now() - start;
  while (bus.handleTimeout(200) > 0) {
  }
  const std::string log = test::read_file(dir.file("stderr"));
  ASSERT_TRUE(exit_status.has_value()) << "the end of the file stops the daemon: " << log;
  EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << log;
  ASSERT_EQ(got.lanes.size(), static_cast<std::size_t>(kFrames)) << log;
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(got.lanes[static_cast<std::size_t>(i)].frame, i);
    EXPECT_EQ(got.lanes[static_cast<std::size_t>(i)].t_ns, times[static_cast<std::size_t>(i)]);
  }
  // Paced: the last frame is due 1.16 s after the first.
  const std::int64_t first = got.lanes.front().capture_utime, last = got.lanes.back().capture_utime;
  EXPECT_GE(last - first, 1'100'000) << "played faster than the file's rate";
  EXPECT_LT(last - first, 3'000'000);
  EXPECT_GE(took, std::chrono::milliseconds(1100));
  EXPECT_NE(log.find("video:" + video + " 800x600 h264 rgb8 25 fps"), std::string::npos) << log;
  ASSERT_FALSE(got.statuses.empty()) << log;
  EXPECT_EQ(got.statuses.back().allocations_since_ready, 0);
}

// [lcm] instance names the daemon in every message instead of "host:pid".
TEST(CcdlanedBus, AConfiguredInstanceNamesEveryMessage) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  BusCapture got(bus);
  test::TempDir dir;
  // config_text ends inside [lcm].
  const std::string config = dir.write("ccdlane.toml", config_text(test::kBusUrl, 30, "instance = \"car7-front\"\n"));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  const auto end = Clock::now() + std::chrono::seconds(15);
  while (got.statuses.size() < 2 && Clock::now() < end) bus.handleTimeout(200);
  child.signal(SIGTERM);
  ASSERT_TRUE(child.wait_exit(2000).has_value());
  const std::string log = test::read_file(dir.file("stderr"));
  ASSERT_GE(got.statuses.size(), 2u) << log;
  ASSERT_FALSE(got.lanes.empty()) << log;
  for (const auto& m : got.statuses) EXPECT_EQ(m.instance, "car7-front");
  for (const auto& m : got.lanes) EXPECT_EQ(m.instance, "car7-front");
  EXPECT_NE(log.find("instance car7-front"), std::string::npos) << log;
}

// A gyro that is there but never answers: a pty whose other side says only garbage, so
// that each handshake drains for drain_max_ms and times out (about 4.5 s for the three
// attempts). SIGTERM must still stop the daemon within about a second, both during the
// start-up handshake and while the gyro thread retries the device; the bound is the one
// --help promises, with room for a loaded machine.
class ChattyGyro {
 public:
  ChattyGyro() {
    char name[64];
    if (openpty(&master_, &slave_, name, nullptr, nullptr) != 0) throw std::runtime_error("openpty");
    path_ = name;
    fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
    talker_ = std::thread([this] {
      // 0x55 is no reply header: the parser skips it all, and the line is never quiet.
      const std::uint8_t garbage[32] = {0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55,
                                        0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55,
                                        0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55, 0x55};
      std::uint8_t commands[256];
      while (!stop_.load()) {
        (void)!write(master_, garbage, sizeof garbage);
        while (read(master_, commands, sizeof commands) > 0) {
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    });
  }
  ~ChattyGyro() {
    stop_.store(true);
    talker_.join();
    close(slave_);
    close(master_);
  }
  const std::string& path() const { return path_; }

 private:
  int master_ = -1, slave_ = -1;  // the slave stays open here: the device never goes away
  std::string path_;
  std::atomic<bool> stop_{false};
  std::thread talker_;
};

Clock::duration time_to_stop(test::ChildProcess& child, const std::string& stderr_path) {
  const auto before = Clock::now();
  child.signal(SIGTERM);
  const std::optional<int> exit_status = child.wait_exit(10000);
  const auto took = Clock::now() - before;
  EXPECT_TRUE(exit_status.has_value()) << "still running 10 s after SIGTERM";
  if (exit_status) {
    EXPECT_TRUE(WIFEXITED(*exit_status));
    EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << test::read_file(stderr_path);
  }
  return took;
}

TEST(Ccdlaned, SigtermDuringASilentGyrosHandshakeStopsWithinASecond) {
  ChattyGyro gyro;
  test::TempDir dir;
  const std::string config =
      dir.write("ccdlane.toml", config_text("memq://", 30, "[gyro]\ndevice = \"" + gyro.path() + "\"\n"));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  // Rendering 10 frames takes well under a second; the handshake then takes seconds.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_FALSE(child.wait_exit(0).has_value()) << test::read_file(dir.file("stderr"));
  const auto took = time_to_stop(child, dir.file("stderr"));
  EXPECT_LT(took, std::chrono::seconds(2)) << test::read_file(dir.file("stderr"));
}

TEST(Ccdlaned, SigtermWhileASilentGyroIsRetriedStopsWithinASecond) {
  ChattyGyro gyro;
  test::TempDir dir;
  const std::string config =
      dir.write("ccdlane.toml", config_text("memq://", 30, "[gyro]\ndevice = \"" + gyro.path() + "\"\n"));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  // Running degraded once the first handshake gave up; then a retry's handshake is under
  // way (backoff 0.5 s, each handshake seconds).
  const auto end = Clock::now() + std::chrono::seconds(20);
  std::string log;
  while (Clock::now() < end && log.find("gyro: warning: absent: ") == std::string::npos) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    log = test::read_file(dir.file("stderr"));
  }
  ASSERT_NE(log.find("gyro: warning: absent: "), std::string::npos) << log;
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_FALSE(child.wait_exit(0).has_value()) << test::read_file(dir.file("stderr"));
  const auto took = time_to_stop(child, dir.file("stderr"));
  EXPECT_LT(took, std::chrono::seconds(2)) << test::read_file(dir.file("stderr"));
}

// Two daemons on one bus: every message names its sender ("host:pid"), and each daemon
// warns once that another instance publishes on its channels.
TEST(CcdlanedBus, TwoDaemonsOnOneBusAreToldApartAndEachWarnsOnce) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  BusCapture got(bus);
  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml", config_text(test::kBusUrl, 30));
  test::ChildProcess a({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("a.stderr"), {}});
  test::ChildProcess b({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("b.stderr"), {}});
  char host[256] = "";
  ASSERT_EQ(gethostname(host, sizeof host - 1), 0);
  const std::string name_a = std::string(host) + ":" + std::to_string(a.pid());
  const std::string name_b = std::string(host) + ":" + std::to_string(b.pid());
  // Each has heard the other's status (sent once a second) before its own next tick.
  const auto statuses_from = [&](const std::string& name) {
    return std::count_if(got.statuses.begin(), got.statuses.end(),
                         [&](const status_t& s) { return s.instance == name; });
  };
  const auto end = Clock::now() + std::chrono::seconds(20);
  while ((statuses_from(name_a) < 3 || statuses_from(name_b) < 3) && Clock::now() < end) bus.handleTimeout(200);
  for (test::ChildProcess* child : {&a, &b}) {
    child->signal(SIGTERM);
    const auto exit_status = child->wait_exit(2000);
    ASSERT_TRUE(exit_status.has_value());
    EXPECT_EQ(WEXITSTATUS(*exit_status), 0);
  }
  int from_a = 0, from_b = 0;
  for (const auto& m : got.lanes) {
    from_a += m.instance == name_a;
    from_b += m.instance == name_b;
  }
  EXPECT_GT(from_a, 0);
  EXPECT_GT(from_b, 0);
  EXPECT_EQ(from_a + from_b, static_cast<int>(got.lanes.size())) << "every lane message names its sender";
  for (const auto& s : got.statuses) EXPECT_TRUE(s.instance == name_a || s.instance == name_b) << s.instance;
  const std::string log_a = test::read_file(dir.file("a.stderr")), log_b = test::read_file(dir.file("b.stderr"));
  EXPECT_EQ(test::count_of(log_a, "another publisher on CCDLANE_STATUS: instance \"" + name_b + "\""), 1) << log_a;
  EXPECT_EQ(test::count_of(log_b, "another publisher on CCDLANE_STATUS: instance \"" + name_a + "\""), 1) << log_b;
  EXPECT_EQ(test::count_of(log_a, "another publisher"), 1) << log_a;
  EXPECT_EQ(test::count_of(log_a, "0 allocations after ready"), 1) << "watching the bus allocates nothing: " << log_a;
}

// A gateway sending garbage (150 m/s: once taken, with false warnings) makes LDW
// unavailable with vehicle_fault, not "available" at the configured speed; status counts
// the refusals by cause and says the vehicle is at fault; the cause is logged once.
TEST(CcdlanedBus, AGatewaySendingImpossibleStatesIsAVehicleFault) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  BusCapture got(bus);
  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml", config_text(test::kBusUrl, 30));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  vehicle_state_t garbage{};
  garbage.speed_mps = 150.0;
  const auto faulted = [&] {
    return std::count_if(got.lanes.begin(), got.lanes.end(), [](const lane_estimate_t& m) {
      return m.ldw_reason == lane_estimate_t::LDW_REASON_VEHICLE_FAULT;
    });
  };
  const auto end = Clock::now() + std::chrono::seconds(20);
  while ((faulted() < 30 || got.statuses.empty() || got.statuses.back().vehicle_state != status_t::VEHICLE_FAULT) &&
         Clock::now() < end) {
    bus.publish("CCDLANE_VEHICLE", &garbage);
    bus.handleTimeout(50);
  }
  ASSERT_TRUE(stops_cleanly(child, bus));
  const std::string log = test::read_file(dir.file("stderr"));
  EXPECT_GE(faulted(), 30) << log;
  for (const lane_estimate_t& m : got.lanes) EXPECT_NE(m.speed_mps, 150.0) << "frame " << m.frame;
  ASSERT_FALSE(got.statuses.empty());
  const status_t& s = got.statuses.back();
  EXPECT_EQ(s.vehicle_state, status_t::VEHICLE_FAULT);
  EXPECT_GT(s.vehicle_refused_by_cause[status_t::VEHICLE_REFUSED_SPEED], 0);
  EXPECT_EQ(s.vehicle_states_total, 0);
  EXPECT_EQ(test::count_of(log, "refused a vehicle_state_t for its speed (speed 150 m/s"), 1) << log;
  EXPECT_EQ(test::count_of(log, "0 allocations after ready"), 1) << "refusing allocates nothing: " << log;
}

// A CAN gateway's vehicle_state_t reaches the daemon's lane departure warning: while it
// publishes, each lane message says the speed and indicator it sent; once it has been
// silent longer than the maximum age (0.5 s), the configured speed, no indicator, and LDW
// unavailable (vehicle_fault). Taking the messages allocates nothing once the daemon is ready.
TEST(CcdlanedBus, TheVehicleStateOnTheBusIsEachFramesInputUntilItGoesStale) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  BusCapture got(bus);
  test::TempDir dir;
  const std::string config = dir.write("ccdlane.toml", config_text(test::kBusUrl, 30, "[vehicle]\nspeed_kmh = 90.0\n"));
  test::ChildProcess child({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  vehicle_state_t state{};
  state.speed_mps = 12.5;
  state.turn_indicator = vehicle_state_t::TURN_INDICATOR_LEFT;
  const auto gateway_lanes = [&] {
    return std::count_if(got.lanes.begin(), got.lanes.end(), [](const lane_estimate_t& m) {
      return m.speed_mps == 12.5 && m.turn_indicator == vehicle_state_t::TURN_INDICATOR_LEFT;
    });
  };
  // The gateway at 20 Hz until 30 lane messages were made with its state.
  for (const auto end = Clock::now() + std::chrono::seconds(20); gateway_lanes() < 30 && Clock::now() < end;) {
    bus.publish("CCDLANE_VEHICLE", &state);
    bus.handleTimeout(50);
  }
  ASSERT_GE(gateway_lanes(), 30) << test::read_file(dir.file("stderr"));
  // Silent: after the maximum age has passed, the frames go back to the configuration.
  const auto silent_from = Clock::now();
  while (Clock::now() - silent_from < std::chrono::milliseconds(1500)) bus.handleTimeout(100);
  const std::size_t first_after = got.lanes.size();
  for (const auto end = Clock::now() + std::chrono::seconds(10);
       got.lanes.size() < first_after + 20 && Clock::now() < end;)
    bus.handleTimeout(100);
  ASSERT_TRUE(stops_cleanly(child, bus));
  ASSERT_GE(got.lanes.size(), first_after + 20);
  for (std::size_t i = first_after; i < got.lanes.size(); ++i) {
    EXPECT_DOUBLE_EQ(got.lanes[i].speed_mps, 90.0 / 3.6) << "frame " << got.lanes[i].frame;
    EXPECT_EQ(got.lanes[i].turn_indicator, vehicle_state_t::TURN_INDICATOR_NONE) << "frame " << got.lanes[i].frame;
    // A gateway that fell silent is a fault: the configured speed is no warning's basis.
    EXPECT_EQ(got.lanes[i].ldw_reason, lane_estimate_t::LDW_REASON_VEHICLE_FAULT) << "frame " << got.lanes[i].frame;
  }
  const std::string log = test::read_file(dir.file("stderr"));
  EXPECT_NE(log.find("vehicle state from CCDLANE_VEHICLE"), std::string::npos) << log;
  EXPECT_EQ(test::count_of(log, "0 allocations after ready"), 1) << "taking vehicle states allocates nothing: " << log;
}

}  // namespace
}  // namespace ccdlane
