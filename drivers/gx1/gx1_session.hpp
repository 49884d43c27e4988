// A 3DM-GX1 device session: brings the sensor up (stop a stream left running, drain,
// firmware and serial number with bounded retries, start streaming), stamps every
// sample with CLOCK_MONOTONIC on arrival, keeps a fixed-size history, and recovers from
// stalls and hang-ups. Driven by one gyro thread through poll_once(); any thread may
// ask attitude_at().
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "drivers/device_state.hpp"
#include "drivers/gx1/attitude_history.hpp"
#include "drivers/gx1/gx1_protocol.hpp"
#include "drivers/gx1/serial_port.hpp"

namespace ccdlane::gx1 {

struct SessionOptions {
  std::uint8_t stream_command = cmd::stab_euler;  // 0x0E, or 0x31 when rates are wanted
  bool continuous = true;                         // false: one poll per reply (for a person at a terminal)
  int reply_timeout_ms = 250;                     // per command reply (a 31-byte reply takes 8 ms on the wire)
  int configure_attempts = 3;                     // stop + drain + firmware handshakes before giving up
  int drain_quiet_ms = 50;                        // the drain ends once the line has been quiet this long
  int drain_max_ms = 1500;                        // ... or after this long, even if a stream will not stop
  int stream_timeout_ms = 1000;                   // no sample for this long while streaming: reconfigure
  std::int64_t max_age_ns = 100'000'000;          // attitude_at(): farther from real samples is stale
  // Refuse (count, log once, keep out of the history) readings no road vehicle can have
  // (vehicle_attitude.hpp): the vehicle's gyro, not a sensor turned in the hand.
  bool vehicle_attitude_only = false;
  BackoffOptions backoff;
};

struct SessionCounters {
  std::uint64_t samples = 0;
  std::uint64_t acks = 0;           // continuous-mode acknowledgements
  std::uint64_t other_replies = 0;  // valid replies nobody asked for
  std::uint64_t bad_checksums = 0;  // from the parser
  std::uint64_t unconfirmed = 0;    // from the parser
  std::uint64_t bytes_skipped = 0;  // from the parser (garbage, damaged replies)
  std::uint64_t bytes_drained = 0;  // discarded while stopping a stream during configuration
  std::uint64_t hangups = 0;
  std::uint64_t reopens = 0;             // back to streaming after a loss
  std::uint64_t configure_failures = 0;  // handshake attempts that got no firmware/serial answer
  std::uint64_t stream_timeouts = 0;
  std::uint64_t poll_timeouts = 0;  // polled mode: a poll without a reply in time
  std::uint64_t refused = 0;        // vehicle_attitude_only: readings beyond a vehicle's attitude
};

class Gx1Session {
 public:
  // `device` is the path opened (and reopened after a hang-up); `log` gets one line per
  // event (stderr when empty).
  explicit Gx1Session(std::string device, SessionOptions options = {}, LogSink log = {});
  ~Gx1Session();
  Gx1Session(const Gx1Session&) = delete;
  Gx1Session& operator=(const Gx1Session&) = delete;

  // Opens and configures; blocks for at most configure_attempts x (drain_max_ms +
  // 3 x reply_timeout_ms). Returns 0 (streaming) or -errno (-ETIMEDOUT: the sensor did
  // not answer). May allocate; nothing after it does.
  int open();
  // The same over an already-open fd (a pty in tests). Reopening after a hang-up goes by
  // the device path, if there is one.
  int open(UniqueFd fd);

  // One step of the gyro thread: waits up to timeout_ms for bytes, decodes and stores
  // samples, runs the watchdog, and when recovering tries to reopen (sleeping out the
  // backoff instead). Returns the number of new samples, or -ENOTCONN when closed.
  // Never throws, never allocates; a reconfiguration inside it blocks as open() does.
  int poll_once(int timeout_ms);

  // Stops continuous mode (best effort) and closes.
  void close();

  // Asked at least every kCancelPollMs while open(), or a reconfiguration in poll_once(),
  // waits for a sensor that does not answer: true abandons the handshake (-ECANCELED),
  // so that stopping never waits out configure_attempts x drain_max_ms. Set before the
  // call that may block, from the thread that makes it.
  void set_cancelled(std::function<bool()> cancelled) { cancelled_ = std::move(cancelled); }
  static constexpr int kCancelPollMs = 50;

  // Any thread. closed: never opened, closed, or the first open failed; recovering: the
  // device went away or stopped answering and is being reopened with backoff.
  DeviceState state() const { return state_.load(std::memory_order_acquire); }
  AttitudeQuery attitude_at(std::int64_t t_ns) const { return history_.attitude_at(t_ns, options_.max_age_ns); }
  const AttitudeHistory& history() const { return history_; }
  std::uint16_t firmware() const { return firmware_.load(std::memory_order_relaxed); }
  std::uint16_t serial_number() const { return serial_number_.load(std::memory_order_relaxed); }
  // The scale of the 0x31 rate vector: EEPROM's GyroGainScale, read at bring-up when
  // streaming 0x31 (else the published default).
  double gyro_gain_scale() const { return gyro_gain_scale_.load(std::memory_order_relaxed); }
  SessionCounters counters() const;
  const std::string& device() const { return port_.path(); }
  const SessionOptions& options() const { return options_; }

 private:
  int configure_opened(int open_result, const char* failure);
  int configure();
  int handshake();
  int read_gyro_gain();
  int drain();
  int await_reply(std::uint8_t header, Reply& out);
  int send(const Frame& frame);
  int stream_step(int timeout_ms);
  int recover_step(int timeout_ms);
  int ingest(std::span<const std::uint8_t> bytes, std::int64_t t_read_ns);
  void lose(const char* what, int error);
  bool refuse_implausible(const Gx1Angles& angles);
  void set_state(DeviceState s) { state_.store(s, std::memory_order_release); }
  void publish_counters();
  template <typename OnReply>
  void parse(std::span<const std::uint8_t> bytes, OnReply on_reply);

  bool cancelled() const { return cancelled_ && cancelled_(); }

  SessionOptions options_;
  LogSink log_;
  std::function<bool()> cancelled_;
  SerialPort port_;
  ReplyParser parser_;
  AttitudeHistory history_;
  std::array<std::uint8_t, 512> read_buf_{};
  std::atomic<DeviceState> state_{DeviceState::closed};
  std::atomic<std::uint16_t> firmware_{0};
  std::atomic<std::uint16_t> serial_number_{0};
  std::atomic<double> gyro_gain_scale_{GainScales{}.gyro};
  std::int64_t last_sample_ns_ = 0;
  std::int64_t poll_sent_ns_ = 0;
  bool poll_outstanding_ = false;
  bool reopen_failure_reported_ = false;
  bool refusal_reported_ = false;

  // Written by the gyro thread, read by anyone: each a relaxed atomic.
  struct Shared {
    std::atomic<std::uint64_t> samples{0}, acks{0}, other_replies{0}, bad_checksums{0}, unconfirmed{0},
        bytes_skipped{0}, bytes_drained{0}, hangups{0}, reopens{0}, configure_failures{0}, stream_timeouts{0},
        poll_timeouts{0}, refused{0};
  } shared_;
};

}  // namespace ccdlane::gx1
