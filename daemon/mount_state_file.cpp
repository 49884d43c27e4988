// Numbers are written with 17 significant digits, so that a mount read back is the mount
// written, bit for bit (the configured mount is compared exactly).
#include "daemon/mount_state_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>

#include "base/temp_file.hpp"

namespace ccdlane {
namespace {

using calibration::LearnedMount;
using calibration::OnlineMountOptions;

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// The directory part of `path` ("." when none), into `out`.
void directory_of(const char* path, char* out, std::size_t size) {
  const char* slash = std::strrchr(path, '/');
  if (!slash) {
    std::snprintf(out, size, ".");
  } else if (slash == path) {
    std::snprintf(out, size, "/");
  } else {
    std::snprintf(out, size, "%.*s", static_cast<int>(slash - path), path);
  }
}

}  // namespace

std::size_t format_mount_state(const LearnedMount& learned, const OnlineMountOptions& options, char* out,
                               std::size_t size) {
  const int n = std::snprintf(
      out, size,
      "# The camera mount ccdlaned learned while driving ([calibration] online). Written by\n"
      "# ccdlaned; delete this file (with ccdlaned stopped) to learn the mount afresh.\n"
      "format = %d\n"
      "# the [attitude] it was learned against: a different configured mount discards it\n"
      "configured_psi_deg = %.17g\n"
      "configured_theta_deg = %.17g\n"
      "# corrections to add to those, degrees: what the frames say, and what was in use\n"
      "estimate_psi_deg = %.17g\n"
      "estimate_theta_deg = %.17g\n"
      "applied_psi_deg = %.17g\n"
      "applied_theta_deg = %.17g\n"
      "# per-frame spread of the solved angles, degrees, and the frames the estimate is made of\n"
      "spread_psi_deg = %.17g\n"
      "spread_theta_deg = %.17g\n"
      "frames = %lld\n",
      kMountStateFormat, options.configured_psi_deg, options.configured_theta_deg, learned.estimate.psi_deg,
      learned.estimate.theta_deg, learned.applied.psi_deg, learned.applied.theta_deg, learned.spread.psi_deg,
      learned.spread.theta_deg, static_cast<long long>(learned.frames));
  return n > 0 && static_cast<std::size_t>(n) < size ? static_cast<std::size_t>(n) : 0;
}

std::string parse_mount_state(std::string_view text, const OnlineMountOptions& options, LearnedMount& learned) {
  std::map<std::string, double, std::less<>> values;
  int line_number = 0;
  while (!text.empty()) {
    const auto end = text.find('\n');
    const std::string_view line = trim(text.substr(0, end));
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    ++line_number;
    if (line.empty() || line.front() == '#') continue;
    const auto eq = line.find('=');
    if (eq == std::string_view::npos) return "line " + std::to_string(line_number) + " is not \"key = value\"";
    const std::string key(trim(line.substr(0, eq)));
    const std::string value(trim(line.substr(eq + 1)));
    char* stop = nullptr;
    errno = 0;
    const double v = std::strtod(value.c_str(), &stop);
    if (value.empty() || *stop != '\0' || errno == ERANGE)
      return key + " is not a number (line " + std::to_string(line_number) + ")";
    if (!std::isfinite(v)) return key + " is not finite (line " + std::to_string(line_number) + ")";
    if (!values.emplace(key, v).second) return key + " is given twice";
  }
  static constexpr const char* kKeys[] = {
      "format",          "configured_psi_deg", "configured_theta_deg", "estimate_psi_deg", "estimate_theta_deg",
      "applied_psi_deg", "applied_theta_deg",  "spread_psi_deg",       "spread_theta_deg", "frames"};
  for (const auto& [key, value] : values) {
    bool known = false;
    for (const char* k : kKeys) known = known || key == k;
    if (!known) return "unknown key " + key;
  }
  if (!values.count("format")) return "no format version";
  if (values["format"] != kMountStateFormat)
    return "format " + std::to_string(values["format"]) + ", this ccdlaned reads format " +
           std::to_string(kMountStateFormat);
  for (const char* k : kKeys)
    if (!values.count(k)) return std::string("no ") + k;

  if (values["configured_psi_deg"] != options.configured_psi_deg ||
      values["configured_theta_deg"] != options.configured_theta_deg) {
    char why[200];
    std::snprintf(why, sizeof why, "learned against [attitude] psi_deg %g theta_deg %g, configured now %g %g",
                  values["configured_psi_deg"], values["configured_theta_deg"], options.configured_psi_deg,
                  options.configured_theta_deg);
    return why;
  }
  const double max = options.max_correction_deg;
  for (const char* k : {"estimate_psi_deg", "estimate_theta_deg", "applied_psi_deg", "applied_theta_deg"})
    if (std::abs(values[k]) > max) {
      char why[160];
      std::snprintf(why, sizeof why, "%s %g lies beyond max_correction_deg %g", k, values[k], max);
      return why;
    }
  for (const char* k : {"spread_psi_deg", "spread_theta_deg"})
    if (values[k] < 0.0 || values[k] > 10.0) return std::string(k) + " is not a spread of 0..10 degrees";
  const double frames = values["frames"];
  if (frames < 1.0 || frames > 1e15 || frames != std::floor(frames)) return "frames is not a count >= 1";

  learned.estimate = {values["estimate_psi_deg"], values["estimate_theta_deg"]};
  learned.applied = {values["applied_psi_deg"], values["applied_theta_deg"]};
  learned.spread = {values["spread_psi_deg"], values["spread_theta_deg"]};
  learned.frames = static_cast<std::int64_t>(frames);
  return "";
}

FileWriteError write_file_atomically(const char* path, const char* data, std::size_t size) {
  char tmp_path[PATH_MAX];
  const int fd = create_temp_beside(path, tmp_path, sizeof tmp_path);
  if (fd < 0) return {"open", -fd};
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : EIO;
      ::close(fd);
      ::unlink(tmp_path);
      return {"write", e};
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int e = errno;
    ::close(fd);
    ::unlink(tmp_path);
    return {"fsync", e};
  }
  if (::close(fd) != 0) {
    const int e = errno;
    ::unlink(tmp_path);
    return {"close", e};
  }
  if (::rename(tmp_path, path) != 0) {
    const int e = errno;
    ::unlink(tmp_path);
    return {"rename", e};
  }
  // The rename itself is durable once the directory is.
  char dir[512];
  directory_of(path, dir, sizeof dir);
  const int dfd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return {"open directory", errno};
  const int synced = ::fsync(dfd);
  const int e = errno;
  ::close(dfd);
  if (synced != 0) return {"fsync directory", e};
  return {};
}

}  // namespace ccdlane
