// ccdlaned's log: one line per event, a category per subsystem, to stderr (the journal
// under systemd). Formats on the stack and writes once: safe on the real-time threads.
#pragma once

#include <atomic>

namespace ccdlane {

// syslog priorities, which journald reads from a "<N>" line prefix.
enum class LogLevel : int { error = 3, warning = 4, notice = 5, info = 6 };

// Writes "ccdlaned: CATEGORY: MESSAGE" (on a terminal, with "warning: "/"error: " before
// the message) or "<N>CATEGORY: MESSAGE" when stderr is the journal (JOURNAL_STREAM set).
// Lines longer than 512 bytes are cut. No allocation.
void log_line(LogLevel level, const char* category, const char* format, ...) __attribute__((format(printf, 3, 4)));

// Where lines go and in which form; for tests (the default is stderr, form from the
// environment at the first line).
void set_log_output(int fd, bool journal_form);

// For "say it once" reports: true the first time it is called on this flag.
inline bool first_time(std::atomic<bool>& said) { return !said.exchange(true, std::memory_order_relaxed); }

}  // namespace ccdlane
