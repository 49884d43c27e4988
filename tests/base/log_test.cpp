// Log lines: one write each, in the terminal or the journal's form, cut but terminated.
#include "base/log.hpp"

#include <unistd.h>

#include <string>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

class LogTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(pipe(fds_), 0); }
  void TearDown() override {
    set_log_output(STDERR_FILENO, false);
    close(fds_[0]);
    close(fds_[1]);
  }
  std::string read_back() {
    char buf[4096];
    const ssize_t n = read(fds_[0], buf, sizeof buf);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  }
  int fds_[2] = {-1, -1};
};

TEST_F(LogTest, TerminalFormNamesTheProgramCategoryAndSeverity) {
  set_log_output(fds_[1], false);
  log_line(LogLevel::warning, "camera", "%s: stalled", "v4l2:/dev/video0");
  EXPECT_EQ(read_back(), "ccdlaned: camera: warning: v4l2:/dev/video0: stalled\n");
  log_line(LogLevel::info, "start", "%d buffers", 6);
  EXPECT_EQ(read_back(), "ccdlaned: start: 6 buffers\n");
}

TEST_F(LogTest, JournalFormCarriesTheSyslogPriority) {
  set_log_output(fds_[1], true);
  log_line(LogLevel::error, "lcm", "bus down");
  EXPECT_EQ(read_back(), "<3>lcm: bus down\n");
  log_line(LogLevel::notice, "config", "SIGHUP");
  EXPECT_EQ(read_back(), "<5>config: SIGHUP\n");
}

TEST_F(LogTest, LongLinesAreCutButStillEndTheLine) {
  set_log_output(fds_[1], false);
  log_line(LogLevel::info, "x", "%s", std::string(2000, 'a').c_str());
  const std::string line = read_back();
  EXPECT_LE(line.size(), 512u);
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1);
}

TEST(FirstTime, IsTrueOnce) {
  std::atomic<bool> said{false};
  EXPECT_TRUE(first_time(said));
  EXPECT_FALSE(first_time(said));
  EXPECT_FALSE(first_time(said));
}

}  // namespace
}  // namespace ccdlane
