// A piece of a test run as another user: in a forked child, so that the test process
// keeps its privileges (a test as root sees what an unprivileged user of ccdlane sees).
#pragma once

#include <grp.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace ccdlane::test {

// How the child ended (waitpid's status), and what it wrote to the descriptor it was given.
struct ChildRun {
  int status = -1;
  std::string out;
  bool exited_with(int code) const { return WIFEXITED(status) && WEXITSTATUS(status) == code; }
};

// Forks; the child runs `before()` while still privileged (exit 10 if it returns false),
// drops its groups and becomes `uid` (exit 11 if it cannot), then exits with
// `body(fd)`, fd the write end of a pipe whose contents the parent returns.
template <typename Before, typename Body>
ChildRun run_as_user(uid_t uid, Before before, Body body) {
  ChildRun run;
  int fds[2];
  if (::pipe(fds) != 0) return run;
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return run;
  }
  if (child == 0) {
    ::close(fds[0]);
    if (!before()) _exit(10);
    if (::setgroups(0, nullptr) != 0 || ::setresgid(uid, uid, uid) != 0 || ::setresuid(uid, uid, uid) != 0) _exit(11);
    _exit(body(fds[1]));
  }
  ::close(fds[1]);
  char buf[4096];
  ssize_t n;
  while ((n = ::read(fds[0], buf, sizeof buf)) > 0) run.out.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  if (::waitpid(child, &run.status, 0) != child) run.status = -1;
  return run;
}

// The unprivileged user ("nobody").
inline constexpr uid_t kNobody = 65534;

}  // namespace ccdlane::test
