// The emulated 3DM-GX1: a thread that owns a pty master, answers commands, streams at
// its own pace, and misbehaves on request.
#include "drivers/gx1/gx1_emulator.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "drivers/device_state.hpp"

namespace ccdlane::gx1 {
namespace {

constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::int64_t kIdleWaitNs = 2 * kNsPerMs;  // the slave is closed: nothing to wait on

std::int16_t rounded_counts(double value) {
  return static_cast<std::int16_t>(std::clamp(std::lround(value), -32768L, 32767L));
}

double wrap180(double d) { return std::remainder(d, 360.0); }

}  // namespace

Gx1Angles circling_attitude(double t_s) {
  const double two_pi = 2.0 * std::numbers::pi;
  return {8.0 * std::sin(two_pi * 0.25 * t_s), -4.0 + 3.0 * std::sin(two_pi * 0.1 * t_s), wrap180(150.0 + 45.0 * t_s)};
}

Gx1Emulator::Gx1Emulator(EmulatorOptions options, LogSink log)
    : options_(std::move(options)), log_(std::move(log)), rng_(options_.seed) {
  period_ns_ = static_cast<std::int64_t>(1e9 / std::max(options_.rate_hz, 0.1));
  streaming_ = options_.left_streaming;
  if (options_.record_limit) sent_.reserve(options_.record_limit);
}

Gx1Emulator::~Gx1Emulator() { stop(); }

int Gx1Emulator::start() {
  if (!options_.link.empty()) {
    struct stat st {};
    if (lstat(options_.link.c_str(), &st) == 0 && !S_ISLNK(st.st_mode)) return -EEXIST;
  }
  t0_ns_ = monotonic_ns();
  next_due_ns_ = t0_ns_ + period_ns_;
  if (const int rc = create_pty(); rc < 0) return rc;
  stop_ = false;
  thread_ = std::thread([this] { run(); });
  return 0;
}

void Gx1Emulator::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  master_.reset();
  remove_link();
}

// A raw 38400 8N1 pty, like a serial line nobody has configured oddly: with the default
// cooked settings the slave would echo the stream back as "commands" before anyone opens it.
int Gx1Emulator::create_pty() {
  termios t{};
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  cfsetispeed(&t, B38400);
  cfsetospeed(&t, B38400);
  int master = -1, slave = -1;
  char name[128] = {};
  if (openpty(&master, &slave, name, &t, nullptr) != 0) return -errno;
  UniqueFd m(master);
  ::close(slave);  // the user opens it by path, as a real device
  if (fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK) < 0 || fcntl(master, F_SETFD, FD_CLOEXEC) < 0)
    return -errno;
  if (!options_.link.empty()) {
    // Re-point atomically: a reader never sees the link missing while a device exists. The
    // new link gets a name of its own (symlink() never replaces one): a user's
    // "<link>.new" is not deleted.
    char tmp[PATH_MAX];
    int rc = -EEXIST;
    for (unsigned k = 0; rc == -EEXIST && k < 100; ++k) {
      std::snprintf(tmp, sizeof tmp, "%s.new.%d.%u", options_.link.c_str(), static_cast<int>(::getpid()), k);
      rc = ::symlink(name, tmp) == 0 ? 0 : -errno;
    }
    if (rc < 0) return rc;
    if (::rename(tmp, options_.link.c_str()) != 0) {
      const int e = errno;
      ::unlink(tmp);
      return -e;
    }
  }
  master_ = std::move(m);
  std::lock_guard lock(mutex_);
  slave_path_ = name;
  return 0;
}

void Gx1Emulator::remove_link() {
  if (options_.link.empty()) return;
  struct stat st {};
  if (lstat(options_.link.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) ::unlink(options_.link.c_str());
}

std::string Gx1Emulator::slave_path() const {
  std::lock_guard lock(mutex_);
  return slave_path_;
}

std::string Gx1Emulator::device_path() const { return options_.link.empty() ? slave_path() : options_.link; }

void Gx1Emulator::inject_garbage(unsigned bytes) { garbage_request_ += bytes; }
void Gx1Emulator::flip_next_packet() { flip_request_ = true; }
void Gx1Emulator::stall(int ms) { stall_request_ms_ = ms; }
void Gx1Emulator::hang_up(int reappear_after_ms) { hangup_request_ms_ = reappear_after_ms; }

EmulatorCounters Gx1Emulator::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

std::vector<SentPacket> Gx1Emulator::sent() const {
  std::lock_guard lock(mutex_);
  return sent_;
}

std::uint16_t Gx1Emulator::ticks_at(std::int64_t now) const {
  const double t_s = static_cast<double>(now - t0_ns_) * 1e-9;
  return static_cast<std::uint16_t>(static_cast<std::uint64_t>(t_s / options_.tick_seconds) & 0xFFFF);
}

void Gx1Emulator::run() {
  std::array<std::uint8_t, 256> buf{};
  while (!stop_) {
    std::int64_t now = monotonic_ns();
    if (const int ms = hangup_request_ms_.exchange(-1); ms >= 0) {
      remove_link();    // like udev removing /dev/ttyUSB0 (first: whoever sees the
      master_.reset();  // hang-up must not find the old path); readers see POLLHUP, read() == 0
      hung_ = true;
      hung_until_ns_ = now + ms * kNsPerMs;
      command_size_ = 0;
      std::lock_guard lock(mutex_);
      ++counters_.hangups;
    }
    if (hung_) {
      if (now < hung_until_ns_) {
        sleep_until(std::min(hung_until_ns_, now + kIdleWaitNs));
        continue;
      }
      if (const int rc = create_pty(); rc < 0) {
        log_to(log_, LogLevel::error, "gyro", "gx1-emulator: cannot create a pty: %s", std::strerror(-rc));
        sleep_until(now + 100 * kNsPerMs);
        continue;
      }
      hung_ = false;
      log_to(log_, LogLevel::info, "gyro", "gx1-emulator: back as %s", slave_path().c_str());
      next_due_ns_ = monotonic_ns() + period_ns_;
    }
    if (const int ms = stall_request_ms_.exchange(0); ms > 0) {
      stalled_until_ns_ = now + ms * kNsPerMs;
      std::lock_guard lock(mutex_);
      ++counters_.stalls;
    }
    if (stalled_until_ns_ != 0) {  // deaf and mute, but stop() still works
      if (now < stalled_until_ns_) {
        sleep_until(std::min(stalled_until_ns_, now + kIdleWaitNs));
        continue;
      }
      stalled_until_ns_ = 0;
      next_due_ns_ = now + period_ns_;  // a stalled sensor does not burst afterwards
    }

    const std::int64_t wait_ns = streaming_ ? std::max<std::int64_t>(next_due_ns_ - now, 0) : 20 * kNsPerMs;
    pollfd p{master_.get(), POLLIN, 0};
    const timespec ts{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    if (ppoll(&p, 1, &ts, nullptr) > 0) {
      if (p.revents & POLLIN) {
        const ssize_t n = ::read(master_.get(), buf.data(), buf.size());
        now = monotonic_ns();
        for (ssize_t i = 0; i < n; ++i) handle_byte(buf[static_cast<std::size_t>(i)], now);
      } else if (p.revents & POLLHUP) {
        // No slave open: the master polls as hung up until someone opens it.
        sleep_until(std::min(now + kIdleWaitNs, now + wait_ns));
      }
    }
    now = monotonic_ns();
    if (streaming_ && now >= next_due_ns_) {
      stream_packet(now);
      next_due_ns_ += period_ns_;
      if (next_due_ns_ < now) next_due_ns_ = now + period_ns_;  // fell behind: don't burst
    }
  }
}

void Gx1Emulator::handle_byte(std::uint8_t b, std::int64_t now) {
  if (command_size_ == 0) {
    command_length_ = command_length(b);
    if (command_length_ == 0) {
      std::lock_guard lock(mutex_);
      ++counters_.unknown_bytes;
      return;
    }
  }
  command_[command_size_++] = b;
  if (command_size_ == command_length_) {
    execute(now);
    command_size_ = 0;
  }
}

void Gx1Emulator::execute(std::int64_t now) {
  const std::uint8_t c = command_[0];
  {
    std::lock_guard lock(mutex_);
    ++counters_.commands;
  }
  switch (c) {
    case cmd::continuous: {
      if (command_[1] != 0x00) return;  // not the fixed confirmation byte: ignored
      const std::uint8_t streamed = command_[2];
      if (streamed != 0 && (reply_length(streamed) == 0 || streamed == cmd::continuous)) return;
      streaming_ = streamed;
      next_due_ns_ = now + period_ns_;
      {
        std::lock_guard lock(mutex_);
        if (streamed == 0) {
          ++counters_.stops;
        } else {
          ++counters_.starts;
          counters_.last_start_ns = now;
        }
      }
      write_reply(ContinuousAck{streamed, ticks_at(now)});
      return;
    }
    case cmd::firmware: write_reply(FirmwareReply{options_.firmware}); return;
    case cmd::serial_number: write_reply(SerialNumberReply{options_.serial_number}); return;
    case cmd::read_eeprom: {
      const std::uint16_t address = static_cast<std::uint16_t>((command_[1] << 8) | command_[2]);
      std::uint16_t value = 0;
      switch (address) {  // the factory values of docs/gx1.md sections 5 and 6
        case kEepromGyroGainScale: value = options_.gyro_gain_scale; break;
        case kEepromAccelGainScale: value = 7000; break;
        case kEepromMagGainScale: value = 2000; break;
        case 238:
        case 240: value = 16; break;
        case 242: value = 256; break;
        case 246: value = 1; break;
        default: break;
      }
      write_reply(EepromReply{value, ticks_at(now)});
      return;
    }
    case cmd::stab_euler:
    case cmd::inst_euler:
    case cmd::stab_euler_vectors:
    case cmd::stab_quaternion:
    case cmd::inst_quaternion:
    case cmd::temperature: write_reply(measurement(c, now)); return;
    default: return;  // a real command this emulator does not model: no answer
  }
}

Reply Gx1Emulator::measurement(std::uint8_t command, std::int64_t now) const {
  const double t_s = static_cast<double>(now - t0_ns_) * 1e-9;
  const Gx1Angles a = options_.attitude(t_s);
  const std::uint16_t ticks = ticks_at(now);
  switch (command) {
    case cmd::stab_euler_vectors: {
      // Level: the accelerometers read -1 G on z (as V3). The rates are the body rates a
      // gyro triad measures: the script's Euler angle rates (by finite difference) through
      // the 3-2-1 kinematics, so that a turn at a pitch or roll reads as the sensor would.
      const Gx1Angles later = options_.attitude(t_s + 1e-3);
      const GainScales gains;
      constexpr double kRad = std::numbers::pi / 180.0;
      const double roll_rate = wrap180(later.roll_deg - a.roll_deg) * kRad / 1e-3;
      const double pitch_rate = wrap180(later.pitch_deg - a.pitch_deg) * kRad / 1e-3;
      const double yaw_rate = wrap180(later.yaw_deg - a.yaw_deg) * kRad / 1e-3;
      const double sr = std::sin(a.roll_deg * kRad), cr = std::cos(a.roll_deg * kRad);
      const double sp = std::sin(a.pitch_deg * kRad), cp = std::cos(a.pitch_deg * kRad);
      const double body[3] = {roll_rate - yaw_rate * sp, pitch_rate * cr + yaw_rate * cp * sr,
                              -pitch_rate * sr + yaw_rate * cp * cr};
      const double counts_per_radps = 32768000.0 / options_.gyro_gain_scale;
      EulerVectorsReply r;
      r.roll = counts_from_degrees(a.roll_deg);
      r.pitch = counts_from_degrees(a.pitch_deg);
      r.yaw = counts_from_degrees(a.yaw_deg);
      r.accel = {0, 0, rounded_counts(-32768000.0 / gains.accel)};
      r.rate = {rounded_counts(body[0] * counts_per_radps), rounded_counts(body[1] * counts_per_radps),
                rounded_counts(body[2] * counts_per_radps)};
      r.ticks = ticks;
      return r;
    }
    case cmd::stab_quaternion:
    case cmd::inst_quaternion: {
      // 3-2-1 (yaw, pitch, roll) Euler angles as a quaternion, scalar first (section 4).
      const double d = std::numbers::pi / 360.0;  // half angle, radians per degree
      const double cr = std::cos(a.roll_deg * d), sr = std::sin(a.roll_deg * d);
      const double cp = std::cos(a.pitch_deg * d), sp = std::sin(a.pitch_deg * d);
      const double cy = std::cos(a.yaw_deg * d), sy = std::sin(a.yaw_deg * d);
      QuaternionReply r;
      r.header = command;
      const double q[4] = {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                           cr * cp * sy - sr * sp * cy};
      for (int i = 0; i < 4; ++i) r.q[static_cast<std::size_t>(i)] = rounded_counts(q[i] * kQuaternionCountsPerUnit);
      r.ticks = ticks;
      return r;
    }
    case cmd::temperature: return TemperatureReply{0x2666, ticks};  // 25 degrees C (V4)
    default:
      return EulerReply{command, counts_from_degrees(a.roll_deg), counts_from_degrees(a.pitch_deg),
                        counts_from_degrees(a.yaw_deg), ticks};
  }
}

void Gx1Emulator::write_reply(const Reply& reply) {
  write_bytes(encode_reply(reply).span(), false);
  std::lock_guard lock(mutex_);
  ++counters_.replies;
}

void Gx1Emulator::stream_packet(std::int64_t now) {
  SentPacket sent;
  {
    std::lock_guard lock(mutex_);
    sent.number = ++counters_.packets;
  }
  const std::uint64_t k = sent.number;
  const PeriodicFaults& f = options_.faults;
  const auto due = [k](unsigned every, unsigned phase) { return every != 0 && k % every == phase; };

  unsigned garbage = garbage_request_.exchange(0);
  if (due(f.garbage_every, f.garbage_phase)) garbage += f.garbage_bytes;
  if (garbage > 0) {
    std::array<std::uint8_t, 64> junk{};
    garbage = std::min<unsigned>(garbage, junk.size());
    for (unsigned i = 0; i < garbage; ++i) junk[i] = static_cast<std::uint8_t>(rng_() & 0xFF);
    write_bytes({junk.data(), garbage}, false);
  }

  sent.reply = measurement(streaming_, now);
  Frame frame = encode_reply(sent.reply);
  const bool flip = flip_request_.exchange(false) || due(f.flip_every, f.flip_phase);
  if (flip) {
    const std::uint32_t bit = static_cast<std::uint32_t>(rng_() % (frame.size * 8u));
    frame.bytes[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    sent.intact = false;
  }
  const bool split = due(f.split_every, 0);
  sent.t_ns = monotonic_ns();
  // Recorded before it is written: whatever a reader has received is already in sent().
  std::size_t record = options_.record_limit;
  {
    std::lock_guard lock(mutex_);
    counters_.garbage_bytes += garbage;
    counters_.flipped += flip ? 1 : 0;
    counters_.split += split ? 1 : 0;
    if (sent_.size() < options_.record_limit) {
      record = sent_.size();
      sent_.push_back(sent);
    }
  }
  if (!write_bytes(frame.span(), split) && sent.intact) {
    std::lock_guard lock(mutex_);
    ++counters_.dropped;
    if (record < sent_.size()) sent_[record].intact = false;
  }
}

// Writes all of `bytes` unless the line will not take them (nobody reading and the pty
// buffer full, or gone). `split`: in two or three pieces with pauses, so readers see
// partial packets as from a sensor that "occasionally slows transmission" (section 7).
bool Gx1Emulator::write_bytes(std::span<const std::uint8_t> bytes, bool split) {
  std::size_t pieces = split ? 2 + rng_() % 2 : 1;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t piece =
        pieces > 1 ? std::max<std::size_t>(1, (bytes.size() - done) / pieces) : bytes.size() - done;
    const ssize_t n = ::write(master_.get(), bytes.data() + done, piece);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      if (pieces > 1) {
        --pieces;
        sleep_until(monotonic_ns() + kNsPerMs);
      }
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) {
      pollfd p{master_.get(), POLLOUT, 0};
      if (::poll(&p, 1, 5) > 0 && (p.revents & POLLOUT)) continue;
    }
    return false;
  }
  return true;
}

}  // namespace ccdlane::gx1
