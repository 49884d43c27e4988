// Shared helpers of the ccdlane subcommands.
#include "tools/ccdlane/command.hpp"

#include <signal.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace ccdlane::cli {
namespace {
volatile sig_atomic_t g_stop = 0;
void on_stop_signal(int) { g_stop = 1; }
}  // namespace

void catch_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);  // the ssh session that ran it dropped: finish as on Ctrl-C
}

bool stop_requested() { return g_stop != 0; }

CLI::Validator number_from_to(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (!text.empty() && end == text.c_str() + text.size() && v >= lo && v <= hi) return "";
        char range[64];
        std::snprintf(range, sizeof range, "from %g to %g", lo, hi);
        return std::string("must be a number ") + range + ", got " + text;
      },
      "NUMBER");
}

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !(v > 0.0) || !std::isfinite(v))
          return "must be a number greater than 0, got " + text;
        return "";
      },
      "POSITIVE");
}

double parse_number(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
    throw UsageError(what + ": not a finite number: \"" + text + "\"");
  return v;
}

}  // namespace ccdlane::cli
