// ccdlane_soak: ccdlaned on the synthetic source for a long run (default 1 h at 60 fps),
// reporting every interval its memory (RSS), open fds, frames processed and dropped and the p99
// capture-to-publish latency, read from its own status and lane messages on the bus.
// A soak, not a test: it measures drift (leaks, growing latency, drops) over time and
// exits 1 only when the daemon dies or stops reporting.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <lcm/lcm-cpp.hpp>

namespace {

using Clock = std::chrono::steady_clock;

struct SoakArgs {
  std::string daemon = CCDLANE_DAEMON_PATH;
  std::string config;  // "" = a synth config written for this run
  double duration_s = 3600.0;
  double interval_s = 60.0;
  double rate_hz = 60.0;
  // A port of its own, so that the soak neither hears nor disturbs other daemons and tests.
  std::string url = "udpm://239.255.76.67:7691?ttl=0&recv_buf_size=8388608";
  std::string prefix = "SOAK_";
};

// VmRSS of `pid` in kB, -1 when it cannot be read (the process is gone).
long rss_kb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
  return -1;
}

// Open file descriptors of `pid` (entries of /proc/PID/fd), -1 when they cannot be read:
// a leak of one per reconnect or per file shows as a count that grows.
long fd_count(pid_t pid) {
  std::error_code ec;
  long n = 0;
  for (std::filesystem::directory_iterator it("/proc/" + std::to_string(pid) + "/fd", ec), end; !ec && it != end;
       it.increment(ec))
    ++n;
  return ec ? -1 : n;
}

std::string write_synth_config(const SoakArgs& a) {
  char path[] = "/tmp/ccdlane-soak-XXXXXX.toml";
  const int fd = mkstemps(path, 5);
  if (fd < 0) throw std::runtime_error(std::string("cannot create a config file: ") + std::strerror(errno));
  close(fd);
  std::ofstream out(path);
  out << "# ccdlane_soak: the built-in synthetic drive at " << a.rate_hz << " fps\n"
      << "[source]\nkind = \"synth\"\nrate_hz = " << a.rate_hz << "\n"
      << "[synth]\nrate_hz = " << a.rate_hz << "\n"
      << "[gyro]\ndevice = \"emulated\"\n"
      << "[lcm]\nurl = \"" << a.url << "\"\nprefix = \"" << a.prefix << "\"\n";
  if (!out.flush()) throw std::runtime_error(std::string("cannot write ") + path);
  return path;
}

// One interval's view of the daemon: every lane message's latency, the last status.
class Listener {
 public:
  Listener(const SoakArgs& a) : bus_(a.url) {
    if (!bus_.good()) throw std::runtime_error("lcm: cannot open " + a.url);
    bus_.subscribeFunction(
        a.prefix + "LANES",
        +[](const lcm::ReceiveBuffer*, const std::string&, const ccdlane::lane_estimate_t* m, Listener* self) {
          self->latencies_us_.push_back(m->latency_us);
          self->ok_ += m->ok ? 1 : 0;
        },
        this);
    bus_.subscribeFunction(
        a.prefix + "STATUS",
        +[](const lcm::ReceiveBuffer*, const std::string&, const ccdlane::status_t* m, Listener* self) {
          self->status_ = *m;
          self->have_status_ = true;
          self->worst_status_p99_us_ = std::max(self->worst_status_p99_us_, m->latency_p99_us);
        },
        this);
  }
  void handle_until(Clock::time_point t) {
    for (auto now = Clock::now(); now < t; now = Clock::now()) {
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(t - now).count();
      bus_.handleTimeout(static_cast<int>(std::clamp<long long>(ms, 1, 200)));
    }
  }
  std::vector<std::int64_t> latencies_us_;
  long long ok_ = 0;
  ccdlane::status_t status_{};
  bool have_status_ = false;
  std::int64_t worst_status_p99_us_ = 0;

 private:
  lcm::LCM bus_;
};

std::int64_t p99(std::vector<std::int64_t>& v) {
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

int run(const SoakArgs& a) {
  const std::string config = a.config.empty() ? write_synth_config(a) : a.config;
  Listener listener(a);  // subscribed before the daemon starts: no message is missed
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    execl(a.daemon.c_str(), a.daemon.c_str(), "--config", config.c_str(), static_cast<char*>(nullptr));
    std::fprintf(stderr, "ccdlane_soak: cannot run %s: %s\n", a.daemon.c_str(), std::strerror(errno));
    _exit(127);
  }
  std::printf("# ccdlane_soak: %s --config %s (pid %d), %.0f s, report every %.0f s\n", a.daemon.c_str(),
              config.c_str(), static_cast<int>(pid), a.duration_s, a.interval_s);
  std::printf("# p99_us: of every lane message's latency_us in the interval; worst_1s_p99_us: of the status\n");
  std::printf("%8s %9s %5s %10s %9s %9s %9s %8s %10s %10s %12s %8s\n", "min", "rss_kB", "fds", "processed", "dropped",
              "not_ok", "lane_msgs", "ok_msgs", "p99_us", "max_us", "worst1s_p99", "allocs");
  std::fflush(stdout);

  const auto start = Clock::now();
  const auto end = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.duration_s));
  const auto step = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.interval_s));
  long long last_processed = 0, last_dropped = 0, last_not_ok = 0;
  int failures = 0;
  for (auto next = start + step; next <= end + std::chrono::milliseconds(1); next += step) {
    listener.latencies_us_.clear();
    listener.ok_ = 0;
    listener.have_status_ = false;
    listener.worst_status_p99_us_ = 0;
    listener.handle_until(next);
    int wstatus = 0;
    if (waitpid(pid, &wstatus, WNOHANG) == pid) {
      std::printf("# ccdlaned exited early (wait status %d)\n", wstatus);
      return 1;
    }
    const ccdlane::status_t& s = listener.status_;
    const long long processed = s.frames_processed_total, dropped = s.frames_dropped_total,
                    not_ok = s.frames_not_ok_total;
    const auto n = static_cast<long long>(listener.latencies_us_.size());
    const std::int64_t max_us = listener.latencies_us_.empty()
                                    ? 0
                                    : *std::max_element(listener.latencies_us_.begin(), listener.latencies_us_.end());
    // processed, dropped, not_ok: from the daemon's last status in the interval (sent once
    // a second); lane_msgs, ok_msgs, p99_us, max_us: of the lane messages received in it.
    std::printf("%8.1f %9ld %5ld %10lld %9lld %9lld %9lld %8lld %10lld %10lld %12lld %8lld\n",
                std::chrono::duration<double>(Clock::now() - start).count() / 60.0, rss_kb(pid), fd_count(pid),
                processed - last_processed, dropped - last_dropped, not_ok - last_not_ok, n, listener.ok_,
                static_cast<long long>(p99(listener.latencies_us_)), static_cast<long long>(max_us),
                static_cast<long long>(listener.worst_status_p99_us_),
                static_cast<long long>(s.allocations_since_ready));
    std::fflush(stdout);
    if (!listener.have_status_) ++failures;
    last_processed = processed;
    last_dropped = dropped;
    last_not_ok = not_ok;
  }
  kill(pid, SIGTERM);
  int wstatus = 0;
  waitpid(pid, &wstatus, 0);
  std::printf("# totals: %lld processed, %lld dropped, %lld not ok; ccdlaned exit status %d\n", last_processed,
              last_dropped, last_not_ok, WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1);
  if (a.config.empty()) std::remove(config.c_str());
  return failures == 0 && WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ccdlane_soak: ccdlaned on the synthetic source for a long run, reporting every interval"};
  SoakArgs a;
  app.add_option("--daemon", a.daemon, "the ccdlaned to run")->capture_default_str();
  app.add_option("--config", a.config, "its configuration (default: synth source at --rate-hz on --url)");
  app.add_option("--duration-s", a.duration_s, "how long to run")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--interval-s", a.interval_s, "report every")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--rate-hz", a.rate_hz, "synth frame rate")->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  app.add_option("--url", a.url, "LCM bus (with --config: the config's)")->capture_default_str();
  app.add_option("--prefix", a.prefix, "channel prefix (with --config: the config's)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    return run(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ccdlane_soak: %s\n", e.what());
    return 2;
  }
}
