// ccdlane's one log: one line per event, a category per subsystem (camera, gyro, lcm,
// ...), the device named in the line, to stderr (the journal under systemd). Formats on
// the stack and writes once: safe on the real-time threads.
#pragma once

#include <atomic>
#include <functional>

namespace ccdlane {

// syslog priorities, which journald reads from a "<N>" line prefix.
enum class LogLevel : int { error = 3, warning = 4, notice = 5, info = 6 };

// Writes "ccdlaned: CATEGORY: MESSAGE" (on a terminal, with "warning: "/"error: " before
// the message) or "<N>CATEGORY: MESSAGE" when stderr is the journal (JOURNAL_STREAM set).
// Lines longer than 512 bytes are cut. No allocation.
void log_line(LogLevel level, const char* category, const char* format, ...) __attribute__((format(printf, 3, 4)));

// Where a component's lines go when its owner wants them (a test collects them, the
// daemon keeps the gyro's last one as its problem): one line, without a newline, with its
// level and category. Called on the component's thread: it must not block for long, and
// must not allocate where the caller must not.
using LogSink = std::function<void(LogLevel level, const char* category, const char* line)>;

// printf-style into a fixed buffer (cut at 512 bytes), then to `sink`, or to log_line()
// when `sink` is empty. Components that log (the drivers) take a LogSink and log through
// this, naming their device on every line.
void log_to(const LogSink& sink, LogLevel level, const char* category, const char* format, ...)
    __attribute__((format(printf, 4, 5)));

// Where lines go and in which form; for tests (the default is stderr, form from the
// environment at the first line).
void set_log_output(int fd, bool journal_form);

// For "say it once" reports: true the first time it is called on this flag.
inline bool first_time(std::atomic<bool>& said) { return !said.exchange(true, std::memory_order_relaxed); }

}  // namespace ccdlane
