// Driver log lines: fixed-size formatting, one write per line.
#include "drivers/gx1/driver_log.hpp"

#include <cstdarg>
#include <cstdio>

namespace ccdlane {

LogSink stderr_log_sink() {
  return [](const char* line) { std::fprintf(stderr, "%s\n", line); };
}

void log_line(const LogSink& sink, const char* format, ...) {
  char line[256];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  if (sink)
    sink(line);
  else
    std::fprintf(stderr, "%s\n", line);
}

}  // namespace ccdlane
