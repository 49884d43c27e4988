// What the session tests share: a link path of their own for the emulator's pty, and a
// session that drains and backs off quickly (the emulator answers at once).
#pragma once

#include <unistd.h>

#include <string>

#include <gtest/gtest.h>

#include "drivers/gx1/gx1_emulator.hpp"
#include "drivers/gx1/gx1_session.hpp"

namespace ccdlane::gx1::test {

inline constexpr std::int64_t kMs = 1'000'000;

// A path under the test temp dir, distinct per process and per `name`.
inline std::string test_link(const std::string& name) {
  return testing::TempDir() + "/gx1-" + name + "-" + std::to_string(getpid());
}

inline SessionOptions quick_session() {
  SessionOptions o;
  o.drain_quiet_ms = 30;
  o.backoff = {20, 200};
  return o;
}

}  // namespace ccdlane::gx1::test
