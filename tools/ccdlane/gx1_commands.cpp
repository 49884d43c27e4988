// `ccdlane gx1` (talk to a 3DM-GX1 and print its angles) and `ccdlane gx1-emulate` (an
// emulated one on a pty, for running everything without the sensor).
#include <signal.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "drivers/device_state.hpp"
#include "drivers/gx1/gx1_emulator.hpp"
#include "drivers/gx1/gx1_session.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"

namespace ccdlane::cli {
namespace {

std::string firmware_text(std::uint16_t n) {
  const gx1::FirmwareVersion v = gx1::firmware_version(n);
  char text[32];
  std::snprintf(text, sizeof text, "%d.%d.%02d", v.major, v.minor, v.build);
  return text;
}

void print_sample(const gx1::Gx1Sample& s, bool json) {
  if (json) {
    print_json_line(std::cout, Json{{"t_ns", s.t_ns},
                                    {"ticks", s.ticks},
                                    {"roll_deg", json_number(s.angles.roll_deg)},
                                    {"pitch_deg", json_number(s.angles.pitch_deg)},
                                    {"yaw_deg", json_number(s.angles.yaw_deg)}});
  } else {
    char line[160];
    std::snprintf(line, sizeof line, "t_ns %lld ticks %5u roll %+9.4f pitch %+9.4f yaw %+9.4f deg\n",
                  static_cast<long long>(s.t_ns), unsigned{s.ticks}, s.angles.roll_deg, s.angles.pitch_deg,
                  s.angles.yaw_deg);
    std::cout << line;
  }
  flush_checked(std::cout, "standard output");  // one line per sample as it comes, also into a pipe
}

struct Gx1Args {
  std::string device;
  bool continuous = false;
  long count = 0;
  bool json = false;
};

int run_gx1(const Gx1Args& args) {
  if (args.count < 0) throw UsageError("--count: must be 0 (until interrupted) or more");
  catch_stop_signals();
  // Firmware and serial number come first on stderr: hold the driver's notes until then.
  std::vector<std::string> held;
  bool holding = true;
  gx1::SessionOptions options;
  options.continuous = args.continuous;
  gx1::Gx1Session session(args.device, options, [&](LogLevel, const char*, const char* line) {
    if (holding)
      held.emplace_back(line);
    else
      std::cerr << line << std::endl;
  });
  if (const int rc = session.open(); rc < 0) {
    const std::string why = "gx1 " + args.device + ": " + gx1::serial_open_error(rc);
    if (rc == -ENOENT || rc == -ENOTDIR || rc == -EACCES || rc == -EISDIR ||
        rc == gx1::SerialPort::kNotACharacterDevice)
      throw UsageError(why);
    throw std::runtime_error(rc == -ETIMEDOUT ? why + " (no answer to the firmware request)" : why);
  }
  std::cerr << "gx1 " << args.device << ": firmware " << firmware_text(session.firmware()) << " (" << session.firmware()
            << "), serial number " << session.serial_number() << std::endl;
  holding = false;
  for (const std::string& line : held) std::cerr << line << std::endl;

  long printed = 0;
  std::uint64_t next = session.history().count();
  while (!stop_requested() && (args.count == 0 || printed < args.count)) {
    session.poll_once(100);
    for (gx1::Gx1Sample s; next < session.history().count() && (args.count == 0 || printed < args.count); ++next) {
      if (!session.history().sample(next, s)) continue;
      print_sample(s, args.json);
      ++printed;
    }
  }
  const gx1::SessionCounters c = session.counters();
  session.close();
  std::cerr << "gx1 " << args.device << ": " << c.samples << " samples, " << c.bad_checksums << " bad checksums, "
            << c.bytes_skipped << " bytes skipped, " << c.hangups << " hang-ups, " << c.reopens << " reopens"
            << std::endl;
  return 0;
}

struct EmulateArgs {
  std::string link;
  double rate_hz = 100.0;
  bool left_streaming = false;
  std::string attitude;
  unsigned garbage_every = 0, flip_every = 0, split_every = 0;
  double stall_every_s = 0.0, hangup_every_s = 0.0;
  int stall_ms = 500, hangup_ms = 1000;
  unsigned seed = 1;
};

gx1::AttitudeScript attitude_from(const std::string& text) {
  if (text.empty()) return gx1::circling_attitude;
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string p; std::getline(in, p, ',');) parts.push_back(p);
  if (parts.size() != 3) throw UsageError("--attitude: expected ROLL,PITCH,YAW in degrees, got \"" + text + "\"");
  const Gx1Angles a{parse_number(parts[0], "--attitude roll"), parse_number(parts[1], "--attitude pitch"),
                    parse_number(parts[2], "--attitude yaw")};
  return [a](double) { return a; };
}

int run_emulate(const EmulateArgs& args) {
  if (!(args.rate_hz > 0.0 && args.rate_hz <= 1000.0)) throw UsageError("--rate: must be in (0, 1000] Hz");
  if (args.stall_ms < 0 || args.hangup_ms < 0) throw UsageError("--stall-ms, --hangup-ms: must be 0 or more");
  if (args.hangup_every_s > 0.0 && args.link.empty())
    throw UsageError("--hangup-every: needs --link (the pty path changes when the device comes back)");
  gx1::EmulatorOptions o;
  o.link = args.link;
  o.rate_hz = args.rate_hz;
  o.left_streaming = args.left_streaming ? gx1::cmd::stab_euler : 0;
  o.attitude = attitude_from(args.attitude);
  o.faults.garbage_every = args.garbage_every;
  o.faults.flip_every = args.flip_every;
  o.faults.flip_phase = args.flip_every / 2;  // apart from the garbage, so no good packet is lost
  o.faults.split_every = args.split_every;
  o.seed = args.seed;

  // Block the stop signals before the emulator thread starts (it inherits the mask) and
  // wait for them here, so they never interrupt the emulator mid-write.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  gx1::Gx1Emulator emulator(o, [](LogLevel, const char*, const char* line) { std::cerr << line << std::endl; });
  if (const int rc = emulator.start(); rc < 0)
    throw std::runtime_error("gx1-emulate: cannot start: " + std::string(std::strerror(-rc)) +
                             (rc == -EEXIST ? " (--link names an existing file that is not a symlink)" : ""));
  std::cout << emulator.device_path() << std::endl;

  const auto every_ns = [](double s) { return static_cast<std::int64_t>(s * 1e9); };
  std::int64_t next_stall = args.stall_every_s > 0 ? monotonic_ns() + every_ns(args.stall_every_s) : 0;
  std::int64_t next_hangup = args.hangup_every_s > 0 ? monotonic_ns() + every_ns(args.hangup_every_s) : 0;
  const timespec tick{0, 50'000'000};
  while (sigtimedwait(&stop_signals, nullptr, &tick) < 0) {
    const std::int64_t now = monotonic_ns();
    if (next_stall && now >= next_stall) {
      emulator.stall(args.stall_ms);
      next_stall = now + every_ns(args.stall_every_s);
    }
    if (next_hangup && now >= next_hangup) {
      emulator.hang_up(args.hangup_ms);
      next_hangup = now + every_ns(args.hangup_every_s);
    }
  }
  emulator.stop();
  const gx1::EmulatorCounters c = emulator.counters();
  std::cerr << "gx1-emulate: " << c.packets << " packets streamed, " << c.replies << " replies, " << c.commands
            << " commands, " << c.garbage_bytes << " garbage bytes, " << c.flipped << " flipped, " << c.split
            << " split, " << c.stalls << " stalls, " << c.hangups << " hang-ups" << std::endl;
  return 0;
}

}  // namespace

CommandAction setup_gx1(CLI::App& sub) {
  auto args = std::make_shared<Gx1Args>();
  sub.add_option("device", args->device, "serial device of the sensor (e.g. /dev/ttyUSB0)")->required();
  sub.add_flag("--continuous", args->continuous, "stream 0x0E in continuous mode instead of polling");
  sub.add_option("--count", args->count, "stop after N samples (default 0: until interrupted)");
  sub.add_flag("--json", args->json,
               "one JSON object per line: {\"t_ns\",\"ticks\",\"roll_deg\",\"pitch_deg\",\"yaw_deg\"}");
  sub.footer(
      "Prints firmware and serial number on stderr, then one line per sample on stdout: the sensor's "
      "gyro-stabilized Euler angles (0x0E) in degrees, sensor convention (not yet mapped to the camera), "
      "stamped with CLOCK_MONOTONIC nanoseconds on arrival. Reopens the device if it goes away.");
  return [args] { return run_gx1(*args); };
}

CommandAction setup_gx1_emulate(CLI::App& sub) {
  auto args = std::make_shared<EmulateArgs>();
  sub.add_option("--link", args->link, "also make PATH a symlink to the pty (kept pointing at it across hang-ups)");
  sub.add_option("--rate", args->rate_hz, "continuous-mode packets per second (default 100)");
  sub.add_flag("--left-streaming", args->left_streaming, "start as if a previous user left 0x0E streaming");
  sub.add_option("--attitude", args->attitude, "a fixed ROLL,PITCH,YAW in degrees (default: gentle motion, turning)");
  sub.add_option("--garbage-every", args->garbage_every, "7 random bytes before every Nth streamed packet");
  sub.add_option("--flip-every", args->flip_every, "flip one bit in every Nth streamed packet");
  sub.add_option("--split-every", args->split_every, "write every Nth streamed packet in pieces");
  // Bounded: 1e300 s once overflowed into "stall every 50 ms". 0: never.
  sub.add_option("--stall-every", args->stall_every_s, "go silent every S seconds (for --stall-ms)")
      ->check(number_from_to(0.0, 86400.0));
  sub.add_option("--stall-ms", args->stall_ms, "how long a stall lasts (default 500)");
  sub.add_option("--hangup-every", args->hangup_every_s, "hang up every S seconds (needs --link)")
      ->check(number_from_to(0.0, 86400.0));
  sub.add_option("--hangup-ms", args->hangup_ms, "how long the device stays away (default 1000)");
  sub.add_option("--seed", args->seed, "random seed for the faults");
  sub.footer(
      "Prints the path to open (the link, else /dev/pts/N) on stdout and runs until SIGINT or SIGTERM; "
      "then prints its counters on stderr.");
  return [args] { return run_emulate(*args); };
}

}  // namespace ccdlane::cli
