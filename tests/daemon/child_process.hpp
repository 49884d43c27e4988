// A program started in the background, for tests that signal it, read what it sends and
// time its exit (a daemon under a test-owned systemd-like supervisor).
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "tests/support/run_process.hpp"  // read_file, for the users of this header

namespace ccdlane::test {

struct ChildOptions {
  std::vector<std::string> env;  // "NAME=value" added to (or replacing in) the environment
  std::string stdout_path;       // "" = inherit
  std::string stderr_path;       // "" = inherit
  std::optional<uid_t> user;     // run as this uid (and gid = uid), with no memlock/rtprio limits
};

class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options = {});
  ~ChildProcess();  // kills (SIGKILL) and reaps it if it is still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int sig) const;
  // The wait status once it exited, nullopt if it is still running after timeout_ms.
  std::optional<int> wait_exit(int timeout_ms);

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
};

}  // namespace ccdlane::test
