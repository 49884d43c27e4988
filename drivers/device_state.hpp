// The bring-up state machine shared by the device drivers, cameras and gyro (closed ->
// opening -> configuring -> streaming, and recovering with bounded, growing backoff),
// and the fixed-size problem text they report without allocating.
#pragma once

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "base/clock.hpp"

namespace ccdlane {

enum class DeviceState : std::uint8_t { closed, opening, configuring, streaming, recovering };

constexpr const char* state_name(DeviceState s) {
  switch (s) {
    case DeviceState::closed: return "closed";
    case DeviceState::opening: return "opening";
    case DeviceState::configuring: return "configuring";
    case DeviceState::streaming: return "streaming";
    case DeviceState::recovering: return "recovering";
  }
  return "?";
}

// When the next reopen attempt is due: the delay doubles after each failure, from min to
// max, and starts over after a success.
class ReopenBackoff {
 public:
  void configure(int min_ms, int max_ms) {
    min_ns_ = std::int64_t{std::max(min_ms, 1)} * 1'000'000;
    max_ns_ = std::max(std::int64_t{max_ms} * 1'000'000, min_ns_);
    delay_ns_ = min_ns_;
  }
  // A device was just lost: the first attempt comes after the minimum delay.
  void start(std::int64_t now_ns) {
    delay_ns_ = min_ns_;
    due_ns_ = now_ns + delay_ns_;
  }
  void failed(std::int64_t now_ns) {
    delay_ns_ = std::min(delay_ns_ * 2, max_ns_);
    due_ns_ = now_ns + delay_ns_;
  }
  std::int64_t due_ns() const { return due_ns_; }
  std::int64_t delay_ns() const { return delay_ns_; }

 private:
  std::int64_t min_ns_ = 100'000'000;
  std::int64_t max_ns_ = 2'000'000'000;
  std::int64_t delay_ns_ = 100'000'000;
  std::int64_t due_ns_ = 0;
};

// The recovering state of a capture() call: tries `bring_up` whenever the backoff says
// so, sleeping in between. True once it succeeds; false when `deadline_ns` comes first.
template <class BringUp>
bool reopen_until(ReopenBackoff& backoff, std::int64_t deadline_ns, BringUp&& bring_up) {
  for (;;) {
    if (monotonic_ns() >= backoff.due_ns()) {
      if (bring_up()) return true;
      backoff.failed(monotonic_ns());
    }
    if (monotonic_ns() >= deadline_ns) return false;
    sleep_until(std::min(backoff.due_ns(), deadline_ns));
  }
}

// One line of text in a fixed buffer: set on the capture path without allocating.
class ProblemText {
 public:
  __attribute__((format(printf, 2, 3))) void set(const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(text_, sizeof text_, fmt, args);
    va_end(args);
  }
  // Adds "; " and the text to what is there.
  __attribute__((format(printf, 2, 3))) void append(const char* fmt, ...) {
    std::size_t at = std::strlen(text_);
    if (at > 0 && at + 2 < sizeof text_) {
      text_[at++] = ';';
      text_[at++] = ' ';
      text_[at] = '\0';
    }
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(text_ + at, sizeof text_ - at, fmt, args);
    va_end(args);
  }
  void clear() { text_[0] = '\0'; }
  bool empty() const { return text_[0] == '\0'; }
  const char* c_str() const { return text_; }
  std::string str() const { return text_; }

 private:
  char text_[512] = {};
};

}  // namespace ccdlane
