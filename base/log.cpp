// The journal understands "<N>" priority prefixes on each line of a service's stderr;
// a person at a terminal reads "warning:"/"error:" better.
#include "base/log.hpp"

#include <unistd.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ccdlane {
namespace {

std::atomic<int> g_fd{STDERR_FILENO};
std::atomic<int> g_journal{-1};  // -1: not decided yet

bool journal_form() {
  int j = g_journal.load(std::memory_order_relaxed);
  if (j < 0) {
    // systemd sets JOURNAL_STREAM when stderr is connected to the journal.
    j = std::getenv("JOURNAL_STREAM") != nullptr ? 1 : 0;
    g_journal.store(j, std::memory_order_relaxed);
  }
  return j == 1;
}

const char* terminal_prefix(LogLevel level) {
  switch (level) {
    case LogLevel::error: return "error: ";
    case LogLevel::warning: return "warning: ";
    default: return "";
  }
}

}  // namespace

void set_log_output(int fd, bool journal) {
  g_fd.store(fd, std::memory_order_relaxed);
  g_journal.store(journal ? 1 : 0, std::memory_order_relaxed);
}

void log_line(LogLevel level, const char* category, const char* format, ...) {
  char line[512];
  int n = journal_form() ? std::snprintf(line, sizeof line, "<%d>%s: ", static_cast<int>(level), category)
                         : std::snprintf(line, sizeof line, "ccdlaned: %s: %s", category, terminal_prefix(level));
  if (n < 0) return;
  std::size_t used = static_cast<std::size_t>(n) < sizeof line ? static_cast<std::size_t>(n) : sizeof line - 1;
  va_list args;
  va_start(args, format);
  const int m = std::vsnprintf(line + used, sizeof line - used, format, args);
  va_end(args);
  if (m > 0)
    used += static_cast<std::size_t>(m) < sizeof line - used ? static_cast<std::size_t>(m) : sizeof line - used - 1;
  if (used >= sizeof line - 1) used = sizeof line - 2;  // keep room for the newline
  line[used++] = '\n';
  // One write per line, so lines from different threads never interleave.
  const ssize_t ignored = ::write(g_fd.load(std::memory_order_relaxed), line, used);
  (void)ignored;
}

void log_to(const LogSink& sink, LogLevel level, const char* category, const char* format, ...) {
  char line[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  if (sink)
    sink(level, category, line);
  else
    log_line(level, category, "%s", line);
}

}  // namespace ccdlane
