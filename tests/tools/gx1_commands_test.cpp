// `ccdlane gx1` against `ccdlane gx1-emulate`, both run as a user would: two processes,
// the emulator's pty behind a link, JSON lines checked value by value.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_process.hpp"

extern char** environ;

namespace ccdlane {
namespace {

// 360/65536 degrees per count: what a fixed attitude reads back as.
double quantised(double deg) { return std::round(deg * 65536.0 / 360.0) * 360.0 / 65536.0; }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// `ccdlane gx1-emulate` in the background; its first stdout line is the device path.
class EmulatorProcess {
 public:
  explicit EmulatorProcess(std::vector<std::string> args) {
    args.insert(args.begin(), {CCDLANE_TOOL, "gx1-emulate"});
    int out[2];
    if (pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int rc = posix_spawn(&pid_, CCDLANE_TOOL, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    if (rc != 0) throw std::runtime_error("cannot start the emulator");
    out_ = out[0];
    // Read the first line (the path), waiting at most 5 s.
    for (char c; path_.empty() || path_.back() != '\n';) {
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 5000) <= 0 || read(out_, &c, 1) != 1) break;
      path_ += c;
    }
    if (!path_.empty() && path_.back() == '\n') path_.pop_back();
  }
  ~EmulatorProcess() {
    if (pid_ > 0) stop(SIGKILL);
    close(out_);
  }
  const std::string& path() const { return path_; }
  // Sends `sig` and returns the exit status (-1 when killed by a signal).
  int stop(int sig = SIGTERM) {
    kill(pid_, sig);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string path_;
};

TEST(Gx1Commands, StreamsJsonLinesFromTheEmulator) {
  test::TempDir dir;
  const std::string link = dir.file("gx1");
  EmulatorProcess emu({"--link", link, "--rate", "100", "--attitude", "12.5,-3.25,179.99"});
  ASSERT_EQ(emu.path(), link);

  const test::ProcessResult r =
      test::run_process({CCDLANE_TOOL, "gx1", link, "--continuous", "--count", "20", "--json"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const auto err = lines_of(r.err);
  ASSERT_FALSE(err.empty());
  EXPECT_EQ(err[0], "gx1 " + link + ": firmware 3.1.02 (3102), serial number 1234");

  const auto out = lines_of(r.out);
  ASSERT_EQ(out.size(), 20u);
  std::int64_t previous_t = 0;
  for (const std::string& line : out) {
    const auto j = nlohmann::ordered_json::parse(line);
    std::vector<std::string> keys;
    for (const auto& [k, v] : j.items()) keys.push_back(k);
    EXPECT_EQ(keys, (std::vector<std::string>{"t_ns", "ticks", "roll_deg", "pitch_deg", "yaw_deg"}));
    EXPECT_EQ(j["roll_deg"].get<double>(), quantised(12.5));
    EXPECT_EQ(j["pitch_deg"].get<double>(), quantised(-3.25));
    EXPECT_EQ(j["yaw_deg"].get<double>(), quantised(179.99));
    const std::int64_t t = j["t_ns"].get<std::int64_t>();
    EXPECT_GT(t, previous_t);
    previous_t = t;
    EXPECT_TRUE(j["ticks"].is_number_unsigned());
  }
  EXPECT_EQ(emu.stop(), 0);
  struct stat st {};
  EXPECT_NE(lstat(link.c_str(), &st), 0) << "the emulator removes its link on SIGTERM";
}

TEST(Gx1Commands, PollsOneLinePerSampleByDefault) {
  test::TempDir dir;
  EmulatorProcess emu({"--link", dir.file("gx1"), "--attitude", "-1,2,-90"});
  const test::ProcessResult r = test::run_process({CCDLANE_TOOL, "gx1", emu.path(), "--count", "3"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const auto out = lines_of(r.out);
  ASSERT_EQ(out.size(), 3u);
  for (const std::string& line : out) {
    long long t = 0;
    unsigned ticks = 0;
    double roll = 0, pitch = 0, yaw = 0;
    ASSERT_EQ(
        std::sscanf(line.c_str(), "t_ns %lld ticks %u roll %lf pitch %lf yaw %lf deg", &t, &ticks, &roll, &pitch, &yaw),
        5)
        << line;
    EXPECT_NEAR(roll, quantised(-1.0), 0.6e-4);  // printed with 4 decimals
    EXPECT_NEAR(pitch, quantised(2.0), 0.6e-4);
    EXPECT_NEAR(yaw, quantised(-90.0), 0.6e-4);
  }
  EXPECT_EQ(emu.stop(SIGINT), 0);
}

TEST(Gx1Commands, KeepsGoingWhenTheDeviceIsUnpluggedAndFaulty) {
  test::TempDir dir;
  EmulatorProcess emu({"--link", dir.file("gx1"), "--rate", "200", "--hangup-every", "0.6", "--hangup-ms", "100",
                       "--garbage-every", "10", "--flip-every", "10", "--split-every", "3"});
  const test::ProcessResult r =
      test::run_process({CCDLANE_TOOL, "gx1", emu.path(), "--continuous", "--count", "200", "--json"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_EQ(lines_of(r.out).size(), 200u);
  EXPECT_NE(r.err.find("hang-up"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("reopened"), std::string::npos) << r.err;
  EXPECT_EQ(emu.stop(), 0);
}

// Its samples into a full device: exit 1 with the reason, not a silent exit 0.
TEST(Gx1Commands, OutputOnAFullDeviceExitsOne) {
  EmulatorProcess emu({});
  ASSERT_FALSE(emu.path().empty());
  const test::ProcessResult r = test::run_process(
      {"/bin/sh", "-c", "exec \"$@\" >/dev/full", "sh", CCDLANE_TOOL, "gx1", emu.path(), "--count", "3", "--json"});
  EXPECT_EQ(r.exit_status, 1) << r.err;
  EXPECT_NE(r.err.find("standard output: cannot write: No space left on device"), std::string::npos) << r.err;
}

TEST(Gx1Commands, BadInputIsOneLineAndExitStatus2) {
  test::TempDir dir;
  const test::ProcessResult missing = test::run_process({CCDLANE_TOOL, "gx1", dir.file("nothing"), "--count", "1"});
  EXPECT_EQ(missing.exit_status, 2);
  EXPECT_EQ(lines_of(missing.err).size(), 1u) << missing.err;
  EXPECT_NE(missing.err.find(dir.file("nothing")), std::string::npos);
  EXPECT_TRUE(missing.out.empty());

  // A regular file is not a device: refused, and not a byte written into it.
  const std::string toml = dir.write("some.toml", "[camera]\n");
  const test::ProcessResult regular = test::run_process({CCDLANE_TOOL, "gx1", toml, "--count", "1"});
  EXPECT_EQ(regular.exit_status, 2) << regular.err;
  EXPECT_NE(regular.err.find("not a character device"), std::string::npos) << regular.err;
  std::ifstream kept(toml);
  std::string first;
  std::getline(kept, first);
  EXPECT_EQ(first, "[camera]");
  EXPECT_TRUE(kept.peek() == std::char_traits<char>::eof()) << "not a byte more";

  const test::ProcessResult rate = test::run_process({CCDLANE_TOOL, "gx1-emulate", "--rate", "0"});
  EXPECT_EQ(rate.exit_status, 2);
  EXPECT_NE(rate.err.find("--rate"), std::string::npos);

  // --stall-every 1e300 once stalled every 50 ms (an overflow).
  const test::ProcessResult huge = test::run_process({CCDLANE_TOOL, "gx1-emulate", "--stall-every", "1e300"});
  EXPECT_EQ(huge.exit_status, 2);
  EXPECT_NE(huge.err.find("--stall-every: must be a number from 0 to 86400, got 1e300"), std::string::npos) << huge.err;

  const test::ProcessResult stall = test::run_process({CCDLANE_TOOL, "gx1-emulate", "--stall-ms", "-5"});
  EXPECT_EQ(stall.exit_status, 2);
  EXPECT_NE(stall.err.find("--stall-ms"), std::string::npos);

  const test::ProcessResult count = test::run_process({CCDLANE_TOOL, "gx1", "/dev/null", "--count", "-1"});
  EXPECT_EQ(count.exit_status, 2);
  EXPECT_NE(count.err.find("--count"), std::string::npos);

  const test::ProcessResult hangup = test::run_process({CCDLANE_TOOL, "gx1-emulate", "--hangup-every", "1"});
  EXPECT_EQ(hangup.exit_status, 2);
  EXPECT_NE(hangup.err.find("--link"), std::string::npos);

  const std::string file = dir.write("not-a-link", "x");
  const test::ProcessResult clobber = test::run_process({CCDLANE_TOOL, "gx1-emulate", "--link", file});
  EXPECT_EQ(clobber.exit_status, 1);
  EXPECT_EQ(lines_of(clobber.err).size(), 1u) << clobber.err;
}

TEST(Gx1Commands, ASilentDeviceIsAFailureNotBadInput) {
  test::TempDir dir;
  // A pty whose other end never answers the firmware request.
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(grantpt(master), 0);
  ASSERT_EQ(unlockpt(master), 0);
  const std::string slave = ptsname(master);
  const test::ProcessResult r = test::run_process({CCDLANE_TOOL, "gx1", slave, "--count", "1"});
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.err.find("firmware"), std::string::npos) << r.err;
  close(master);
}

}  // namespace
}  // namespace ccdlane
