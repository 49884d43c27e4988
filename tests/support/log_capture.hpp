// Test support: what base/log writes while a LogCapture lives, read back as text, and how
// often a phrase occurs in it (a problem must be told once).
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "base/log.hpp"
#include "tests/support/count_of.hpp"

namespace ccdlane::test {

// The log goes to a pipe (non-blocking, so text() never waits) and back to stderr after.
class LogCapture {
 public:
  LogCapture() {
    EXPECT_EQ(pipe2(fds_, O_NONBLOCK), 0);
    set_log_output(fds_[1], false);
  }
  ~LogCapture() {
    set_log_output(STDERR_FILENO, false);
    close(fds_[0]);
    close(fds_[1]);
  }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  // Everything logged so far (it may be called again as more is logged).
  std::string text() {
    char buf[4096];
    ssize_t n;
    while ((n = read(fds_[0], buf, sizeof buf)) > 0) all_.append(buf, static_cast<std::size_t>(n));
    return all_;
  }

 private:
  int fds_[2] = {-1, -1};
  std::string all_;
};

}  // namespace ccdlane::test
