// How the gyro driver reports what happened (opened, hang-up, reopened): one line at a
// time to a sink the caller chooses (stderr, the journal, a test). Formatting uses a
// stack buffer, so reporting from the streaming path never allocates.
#pragma once

#include <functional>

namespace ccdlane {

// Receives one line without a trailing newline. Calling it must not allocate on paths
// that must not allocate; the default sink writes to stderr.
using LogSink = std::function<void(const char* line)>;

LogSink stderr_log_sink();

// printf-style: formats into a fixed buffer (truncating) and hands the line to `sink`
// (stderr when `sink` is empty).
[[gnu::format(printf, 2, 3)]] void log_line(const LogSink& sink, const char* format, ...);

}  // namespace ccdlane
