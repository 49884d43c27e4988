// `ccdlaned`: the daemon's command line. With no --config and no default file it runs
// the built-in demo, so a fresh install shows lane messages at once.
#include <sys/stat.h>

#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "app/config_loader.hpp"
#include "daemon/daemon.hpp"

namespace {
constexpr const char* kDefaultConfig = "/etc/ccdlane/ccdlane.toml";

bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ccdlaned: lanes from one camera with a known CCD geometry, published over LCM"};
  std::string config_path;
  bool check_only = false;
  app.add_option("--config", config_path,
                 std::string("configuration file (TOML); default ") + kDefaultConfig +
                     ", or the built-in demo when that does not exist");
  app.add_flag("--check-config", check_only, "validate the configuration and exit (0: usable, 2: not)");
  app.set_version_flag("--version", std::string(CCDLANE_VERSION));
  app.footer(
      "Signals: SIGTERM and SIGINT stop it cleanly within a second. SIGHUP does not reload the configuration "
      "(that is logged, and the daemon carries on): restart it to apply a changed file.\n"
      "Under systemd (Type=notify) it sends READY=1 after the first processed frame, WATCHDOG=1 only while "
      "frames are processed, a one-line STATUS= every second and STOPPING=1 on shutdown.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "ccdlaned: %s (see ccdlaned --help)\n", e.what());
    return 2;
  }

  ccdlane::Config config;
  std::string source_name;
  try {
    if (!config_path.empty() || exists(kDefaultConfig)) {
      source_name = config_path.empty() ? kDefaultConfig : config_path;
      config = ccdlane::load_config_file(source_name);
    } else {
      source_name = "the built-in demo";
      config = ccdlane::demo_config();
      if (!check_only)
        std::fprintf(stderr, "ccdlaned: no configuration (%s does not exist): running the built-in demo\n",
                     kDefaultConfig);
    }
  } catch (const ccdlane::ConfigError& e) {
    std::fprintf(stderr, "ccdlaned: %s\n", e.what());
    return 2;
  }
  if (const std::string problem = ccdlane::daemon_config_problem(config); !problem.empty()) {
    std::fprintf(stderr, "ccdlaned: %s: %s\n", source_name.c_str(), problem.c_str());
    return 2;
  }
  if (check_only) {
    std::printf("%s: configuration ok\n", source_name.c_str());
    return 0;
  }
  return ccdlane::run_daemon(config);
}
