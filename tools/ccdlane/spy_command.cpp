// `ccdlane spy`: LCM's lcm-spy with the ccdlane message types on its class path, so a
// person sees the lane, status and frame messages decoded field by field. Debian's own
// /usr/bin/lcm-spy cannot be used: it passes -Xincgc (refused by Java 17) and ignores
// CLASSPATH (platform-notes.md), so this starts the Spy class itself.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/config.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {
namespace {

// Where Debian's liblcm-java and libjchart2d-java (lcm-spy's charts) put their jars.
constexpr const char* kLcmJar = "/usr/share/java/lcm.jar";
constexpr const char* kJchart2dJar = "/usr/share/java/jchart2d.jar";
// The jar of the ccdlane types: where the package installs it, then where this build
// tree made it (for a ccdlane run from the build tree).
constexpr const char* kTypesJars[] = {CCDLANE_LCMTYPES_JAR_INSTALLED, CCDLANE_LCMTYPES_JAR_BUILD};

struct SpyArgs {
  std::string url = LcmConfig{}.url;
  bool print_command = false;
};

bool is_file(const std::string& path) {
  struct stat st {};
  return !path.empty() && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string find_in_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t begin = 0;
  while (begin <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', begin), dirs.size());
    const std::string dir = end > begin ? dirs.substr(begin, end - begin) : ".";
    const std::string candidate = dir + "/" + program;
    if (is_file(candidate) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    begin = end + 1;
  }
  return "";
}

std::string types_jar() {
  std::string looked;
  for (const char* jar : kTypesJars) {
    if (is_file(jar)) return jar;
    if (*jar) looked += std::string(looked.empty() ? "" : ", ") + jar;
  }
  throw std::runtime_error("spy: the jar of the ccdlane LCM types is missing (looked for " + looked +
                           "); reinstall the ccdlane package, or build the target ccdlane_lcmtypes_java");
}

int spy(const SpyArgs& a) {
  const std::string java = find_in_path("java");
  if (java.empty())
    throw std::runtime_error("spy: no java on PATH; install a Java runtime with AWT: apt-get install default-jre");
  const std::pair<const char*, const char*> needed[] = {{kLcmJar, "liblcm-java"}, {kJchart2dJar, "libjchart2d-java"}};
  for (const auto& [jar, package] : needed)
    if (!is_file(jar)) throw std::runtime_error(std::string("spy: ") + jar + " is missing; apt-get install " + package);
  std::string classpath = std::string(kLcmJar) + ":" + kJchart2dJar + ":" + types_jar();
  // The user's own types (their CLASSPATH) are found too.
  if (const char* user = std::getenv("CLASSPATH"); user && *user) classpath += std::string(":") + user;

  const std::vector<std::string> argv = {java, "-Djava.net.preferIPv4Stack=true", "lcm.spy.Spy", "--lcm-url=" + a.url};
  if (a.print_command) {
    std::printf("CLASSPATH=%s", classpath.c_str());
    for (const std::string& arg : argv) std::printf(" '%s'", arg.c_str());
    std::printf("\n");
    return 0;
  }
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!display || !*display) && (!wayland || !*wayland))
    throw std::runtime_error(
        "spy: lcm-spy is a graphical program and there is no display (DISPLAY is not set); "
        "run it in a desktop session, over ssh -X, or under xvfb-run");

  if (::setenv("CLASSPATH", classpath.c_str(), 1) != 0) throw std::runtime_error("spy: cannot set CLASSPATH");
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  // Replace this process, so that signals (Ctrl-C, a service manager's SIGTERM) and the
  // exit status are java's own.
  ::execv(java.c_str(), args.data());
  throw std::runtime_error("spy: cannot start " + java + ": " + std::strerror(errno));
}

}  // namespace

CommandAction setup_spy(CLI::App& sub) {
  auto a = std::make_shared<SpyArgs>();
  sub.add_option("--lcm", a->url, "LCM bus URL ([lcm] url of the daemon)")->capture_default_str();
  sub.add_flag("--print-command", a->print_command,
               "print the class path and the java command instead of starting it (checks that all are there)");
  sub.footer(
      "Starts lcm-spy (java lcm.spy.Spy) with lcm.jar, jchart2d.jar and the ccdlane types jar on its class "
      "path (plus $CLASSPATH, for your own types): every channel with its rate, and the fields of "
      "lane_estimate_t, status_t and frame_t messages. Needs a display (DISPLAY). To see raw frames "
      "([lcm] publish_frames) add &recv_buf_size=8388608 to the URL. Exit 1 when java or a jar is missing.");
  return [a] { return spy(*a); };
}

}  // namespace ccdlane::cli
