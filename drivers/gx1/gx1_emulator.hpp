// A 3DM-GX1 emulator on the master side of a pty pair: answers the commands ccdlane
// uses, streams in continuous mode at its own pace (a pty does not pace) with a
// scripted attitude, and injects faults (garbage, flipped bits, split writes, stalls,
// hang-ups). For tests, and for running the daemon without the sensor.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "base/gx1_angles.hpp"
#include "base/log.hpp"
#include "base/unique_fd.hpp"
#include "drivers/gx1/gx1_protocol.hpp"

namespace ccdlane::gx1 {

// The attitude the emulated sensor reports at `t_s` seconds after it was switched on.
using AttitudeScript = std::function<Gx1Angles(double t_s)>;

// Rolls and pitches gently and turns at 45 degrees/s, so yaw crosses +-180 within the
// first second and every 8 s after.
Gx1Angles circling_attitude(double t_s);

// Faults repeated by streamed-packet number k = 1, 2, ...: "every N" applies where
// k % N == phase (N = 0: off).
struct PeriodicFaults {
  unsigned garbage_every = 0, garbage_phase = 0;
  unsigned garbage_bytes = 7;               // random bytes written just before the packet
  unsigned flip_every = 0, flip_phase = 0;  // one random bit of the packet flipped
  unsigned split_every = 0;                 // the packet written in pieces, 1 ms apart
};

struct EmulatorOptions {
  std::string link;                 // a stable path re-pointed at each new pty ("" = none)
  double rate_hz = 100.0;           // continuous-mode packets per second
  std::uint8_t left_streaming = 0;  // a stream left running by a previous user (0: quiet)
  std::uint16_t firmware = 3102;
  std::uint16_t serial_number = 1234;
  // This unit's GyroGainScale (EEPROM 130), by which its 0x31 rate vector is scaled.
  std::uint16_t gyro_gain_scale = 8500;
  double tick_seconds = kFactoryTickSeconds;
  AttitudeScript attitude = circling_attitude;
  PeriodicFaults faults;
  std::uint32_t seed = 1;
  std::size_t record_limit = 0;  // streamed packets kept for sent() (0: none)
};

// One streamed packet as the emulator wrote it.
struct SentPacket {
  std::uint64_t number = 0;  // k, 1-based
  std::int64_t t_ns = 0;     // CLOCK_MONOTONIC just before its first byte was written
  Reply reply;               // what it encodes (before any flipped bit)
  bool intact = true;        // false: a bit was flipped, or the write was cut short
};

struct EmulatorCounters {
  std::uint64_t packets = 0;        // streamed packets
  std::uint64_t replies = 0;        // answers to polls and commands
  std::uint64_t commands = 0;       // complete commands received
  std::uint64_t stops = 0;          // `10 00 00` received
  std::uint64_t starts = 0;         // `10 00 CC` received
  std::uint64_t unknown_bytes = 0;  // bytes that began no known command
  std::uint64_t garbage_bytes = 0;
  std::uint64_t flipped = 0;
  std::uint64_t split = 0;
  std::uint64_t dropped = 0;  // packets not written whole (nobody reading, buffer full)
  std::uint64_t stalls = 0;
  std::uint64_t hangups = 0;
  std::int64_t last_start_ns = 0;  // when the last `10 00 CC` was received
};

class Gx1Emulator {
 public:
  explicit Gx1Emulator(EmulatorOptions options, LogSink log = {});
  ~Gx1Emulator();
  Gx1Emulator(const Gx1Emulator&) = delete;
  Gx1Emulator& operator=(const Gx1Emulator&) = delete;

  // Creates the pty (and the link) and starts the emulator thread. 0 or -errno
  // (-EEXIST: the link path exists and is not a symlink).
  int start();
  void stop();

  // The slave side to open: /dev/pts/N of the current pty pair.
  std::string slave_path() const;
  // The link if there is one, else the slave path.
  std::string device_path() const;

  // Scripted faults; thread-safe, applied by the emulator thread at the next packet.
  void inject_garbage(unsigned bytes);
  void flip_next_packet();
  void stall(int ms);                   // sends and answers nothing for `ms`
  void hang_up(int reappear_after_ms);  // closes the master (readers see a hang-up);
                                        // a new pty appears later behind the link

  EmulatorCounters counters() const;
  std::vector<SentPacket> sent() const;

 private:
  void run();
  int create_pty();
  void remove_link();
  void handle_byte(std::uint8_t b, std::int64_t now);
  void execute(std::int64_t now);
  Reply measurement(std::uint8_t command, std::int64_t now) const;
  void stream_packet(std::int64_t now);
  bool write_bytes(std::span<const std::uint8_t> bytes, bool split);
  void write_reply(const Reply& reply);
  std::uint16_t ticks_at(std::int64_t now) const;

  EmulatorOptions options_;
  LogSink log_;
  std::int64_t t0_ns_ = 0;
  std::int64_t period_ns_ = 0;
  UniqueFd master_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mt19937 rng_;

  // Emulator thread only.
  std::uint8_t streaming_ = 0;
  std::array<std::uint8_t, 8> command_{};
  std::size_t command_size_ = 0, command_length_ = 0;
  std::int64_t next_due_ns_ = 0;
  std::int64_t hung_until_ns_ = 0;
  std::int64_t stalled_until_ns_ = 0;
  bool hung_ = false;

  // Requests from other threads.
  std::atomic<unsigned> garbage_request_{0};
  std::atomic<bool> flip_request_{false};
  std::atomic<int> stall_request_ms_{0};
  std::atomic<int> hangup_request_ms_{-1};

  mutable std::mutex mutex_;  // guards what follows
  std::string slave_path_;
  EmulatorCounters counters_;
  std::vector<SentPacket> sent_;
};

}  // namespace ccdlane::gx1
