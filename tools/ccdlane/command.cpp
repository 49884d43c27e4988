// Shared helpers of the ccdlane subcommands.
#include "tools/ccdlane/command.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace ccdlane::cli {

double parse_number(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
    throw UsageError(what + ": not a finite number: \"" + text + "\"");
  return v;
}

}  // namespace ccdlane::cli
