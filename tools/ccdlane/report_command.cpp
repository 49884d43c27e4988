// `ccdlane report`: a drive's replay output as plots over time and a summary, in one
// self-contained HTML page (and PNG files), drawn by matplotlib in
// tools/report/ccdlane_report.py, which this finds and runs.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/config_loader.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {
namespace {

// Debian's python3 (with python3-matplotlib), not whatever python3 comes first on PATH.
constexpr const char* kPython = "/usr/bin/python3";
// The script: where the package installs it, then in the source tree (ccdlane run from
// its build tree).
constexpr const char* kScripts[] = {CCDLANE_REPORT_SCRIPT_INSTALLED, CCDLANE_REPORT_SCRIPT_SOURCE};

struct ReportArgs {
  std::string replay;
  std::string out;
  std::string png;
  std::string config;
};

bool is_file(const char* path) {
  struct stat st {};
  return *path && ::stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int report(const ReportArgs& a) {
  if (a.out.empty() && a.png.empty()) throw UsageError("report: give --out FILE.html, --png DIR, or both");
  const char* script = nullptr;
  for (const char* s : kScripts)
    if (is_file(s)) script = s;
  if (!script)
    throw std::runtime_error(std::string("report: ccdlane_report.py is missing (looked for ") + kScripts[0] + ", " +
                             kScripts[1] + "); reinstall the ccdlane package");
  if (!is_file(kPython)) throw std::runtime_error("report: no /usr/bin/python3; apt-get install python3-matplotlib");
  // The warning lines of the offset plot are where the configured vehicle's front wheel
  // meets the configured warning lines.
  const Config config = a.config.empty() ? default_config() : load_config_file(a.config);
  std::vector<std::string> argv = {kPython,
                                   script,
                                   a.replay,
                                   "--vehicle-width-mm",
                                   std::to_string(config.vehicle.width_mm),
                                   "--earliest-warning-mm",
                                   std::to_string(config.ldw.warning.earliest_warning_mm),
                                   "--latest-warning-mm",
                                   std::to_string(config.ldw.warning.latest_warning_mm)};
  if (!a.out.empty()) argv.insert(argv.end(), {"--out", a.out});
  if (!a.png.empty()) argv.insert(argv.end(), {"--png", a.png});
  std::vector<char*> args;
  for (std::string& arg : argv) args.push_back(arg.data());
  args.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  // Replace this process: the exit status (2 for a bad replay file) is the script's own.
  ::execv(kPython, args.data());
  throw std::runtime_error(std::string("report: cannot start ") + kPython + ": " + std::strerror(errno));
}

}  // namespace

CommandAction setup_report(CLI::App& sub) {
  auto a = std::make_shared<ReportArgs>();
  sub.add_option("replay", a->replay, "ccdlane replay's JSON Lines (--out) of a drive")->required();
  sub.add_option("--out", a->out, "write the report here: one HTML page, pictures inline, no network needed");
  sub.add_option("--png", a->png, "write each plot as DIR/<name>.png");
  sub.add_option("--config", a->config,
                 "the configuration replay ran with: [vehicle] width_mm and [ldw] warning lines for the offset plot "
                 "(else the defaults)");
  sub.footer(
      "Plots over time: lateral offset with the lane's lines and the warning lines, lane width, heading and "
      "curvature, DLC and TLC left/right, LDW availability and warnings, the frames not ok by reason, and the "
      "processing time; a table of frames, ok %, lane width mean +/- sd, tightest radius (\"straight\" at 10 km "
      "and beyond), warnings, ms per frame and the longest stretch not ok. Needs python3-matplotlib.");
  return [a] { return report(*a); };
}

}  // namespace ccdlane::cli
