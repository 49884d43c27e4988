// The 3DM-GX1 session: the bring-up of docs/gx1.md section 9.1, continuous streaming of
// section 7, arrival timestamps, and the recovery state machine.
#include "drivers/gx1/gx1_session.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "drivers/device_state.hpp"
#include "drivers/gx1/vehicle_attitude.hpp"

namespace ccdlane::gx1 {
namespace {

constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr int kCommandWriteTimeoutMs = 100;

void bump(std::atomic<std::uint64_t>& counter, std::uint64_t by = 1) {
  counter.fetch_add(by, std::memory_order_relaxed);
}

}  // namespace

Gx1Session::Gx1Session(std::string device, SessionOptions options, LogSink log)
    : options_(options), log_(log), port_(std::move(device), std::move(log), options.backoff) {}

Gx1Session::~Gx1Session() { close(); }

int Gx1Session::open() {
  set_state(DeviceState::opening);
  return configure_opened(port_.open(), "cannot open");
}

int Gx1Session::open(UniqueFd fd) {
  set_state(DeviceState::opening);
  return configure_opened(port_.adopt(std::move(fd)), "cannot use the given fd");
}

int Gx1Session::configure_opened(int open_result, const char* failure) {
  if (open_result < 0) {
    log_to(log_, LogLevel::warning, "gyro", "gx1 %s: %s: %s", device().c_str(), failure,
           serial_open_error(open_result));
    set_state(DeviceState::closed);
    return open_result;
  }
  const int rc = configure();
  if (rc < 0) {
    port_.close();
    set_state(DeviceState::closed);
  }
  return rc;
}

void Gx1Session::close() {
  if (port_.is_open() && options_.continuous &&
      (state() == DeviceState::streaming || state() == DeviceState::configuring)) {
    // Leave the sensor quiet for the next user; closing could discard unsent bytes.
    if (send(encode_continuous_stop()) == 0) (void)port_.drain_output();
  }
  port_.close();
  set_state(DeviceState::closed);
}

int Gx1Session::send(const Frame& frame) { return port_.write_all(frame.span(), kCommandWriteTimeoutMs); }

// Feeds `bytes` through the parser and hands every reply found to on_reply.
template <typename OnReply>
void Gx1Session::parse(std::span<const std::uint8_t> bytes, OnReply on_reply) {
  ParsedReply parsed;
  do {
    bytes = bytes.subspan(parser_.feed(bytes));
    while (parser_.next(parsed)) on_reply(parsed);
  } while (!bytes.empty());
}

// Bounded retries of the whole handshake: a stop that was lost, a reply that was
// damaged, or a sensor still finishing a stream all heal on the next attempt.
int Gx1Session::configure() {
  set_state(DeviceState::configuring);
  int rc = -ETIMEDOUT;
  for (int attempt = 0; attempt < options_.configure_attempts; ++attempt) {
    rc = handshake();
    if (rc == 0 || rc == -ECANCELED || SerialPort::is_hangup_error(-rc)) break;
    bump(shared_.configure_failures);
  }
  if (rc == -ECANCELED) return rc;  // stopping: not the sensor's failure
  if (rc < 0) {
    log_to(log_, LogLevel::warning, "gyro",
           "gx1 %s: no usable answer to the firmware/serial requests after %d attempts: %s", device().c_str(),
           options_.configure_attempts, std::strerror(-rc));
    publish_counters();
    return rc;
  }
  // Start streaming (or polling) from a clean line.
  parser_.reset();
  poll_outstanding_ = false;
  if (options_.continuous) {
    parser_.expect({cmd::continuous, options_.stream_command});
    parser_.confirm_resync(true);
    if (const int s = send(encode_continuous_start(options_.stream_command)); s < 0) return s;
  } else {
    parser_.expect({options_.stream_command});
    parser_.confirm_resync(false);  // a polled reply has no follower to confirm it
  }
  last_sample_ns_ = monotonic_ns();
  set_state(DeviceState::streaming);
  publish_counters();
  return 0;
}

// docs/gx1.md section 9.1: stop whatever a previous user left running, drain, flush, then
// confirm the link with the firmware number and read the serial number.
int Gx1Session::handshake() {
  if (const int rc = send(encode_continuous_stop()); rc < 0) return rc;
  if (const int rc = drain(); rc < 0) return rc;
  if (const int rc = port_.flush(); rc < 0) return rc;
  parser_.reset();
  parser_.confirm_resync(false);  // single replies: nothing follows them

  Reply reply;
  parser_.expect({cmd::firmware});
  if (const int rc = send(encode_poll(cmd::firmware)); rc < 0) return rc;
  if (const int rc = await_reply(cmd::firmware, reply); rc < 0) return rc;
  firmware_.store(std::get_if<FirmwareReply>(&reply)->number, std::memory_order_relaxed);

  parser_.expect({cmd::serial_number});
  if (const int rc = send(encode_poll(cmd::serial_number)); rc < 0) return rc;
  if (const int rc = await_reply(cmd::serial_number, reply); rc < 0) return rc;
  serial_number_.store(std::get_if<SerialNumberReply>(&reply)->number, std::memory_order_relaxed);
  if (options_.stream_command == cmd::stab_euler_vectors) return read_gyro_gain();
  return 0;
}

// The rate vector's scale is the unit's own (docs/gx1.md section 5): read from EEPROM,
// with the published default when the sensor does not answer (rates then within the
// units' spread of that default, the angles unaffected).
int Gx1Session::read_gyro_gain() {
  Reply reply;
  parser_.expect({cmd::read_eeprom});
  if (const int rc = send(encode_eeprom_read(kEepromGyroGainScale)); rc < 0) return rc;
  const int rc = await_reply(cmd::read_eeprom, reply);
  if (rc < 0 && rc != -ETIMEDOUT) return rc;
  const std::uint16_t value = rc == 0 ? std::get_if<EepromReply>(&reply)->value : 0;
  if (value == 0) {
    log_to(log_, LogLevel::warning, "gyro", "gx1 %s: no gyro gain in EEPROM %u (%s); rates scaled by the default %.0f",
           device().c_str(), kEepromGyroGainScale, rc == 0 ? "it reads 0" : "no answer", GainScales{}.gyro);
    gyro_gain_scale_.store(GainScales{}.gyro, std::memory_order_relaxed);
  } else {
    gyro_gain_scale_.store(value, std::memory_order_relaxed);
  }
  return 0;
}

// Reads and discards until the line has been quiet for drain_quiet_ms (a stream that
// was stopped has ended) or drain_max_ms have passed (one that will not stop: the
// firmware reply is still found among its bytes by the parser).
int Gx1Session::drain() {
  const std::int64_t start = monotonic_ns();
  const std::int64_t hard_end = start + options_.drain_max_ms * kNsPerMs;
  std::int64_t quiet_end = start + options_.drain_quiet_ms * kNsPerMs;
  for (;;) {
    const std::int64_t now = monotonic_ns();
    const std::int64_t end = std::min(quiet_end, hard_end);
    if (now >= end) return 0;
    if (cancelled()) return -ECANCELED;
    const int wait_ms = std::min(static_cast<int>((end - now + kNsPerMs - 1) / kNsPerMs), kCancelPollMs);
    const ReadResult r = port_.read_some(read_buf_, wait_ms);
    if (r.status == ReadStatus::hangup || r.status == ReadStatus::error) return -r.error;
    if (r.status == ReadStatus::data) {
      bump(shared_.bytes_drained, r.bytes);
      quiet_end = r.t_ns + options_.drain_quiet_ms * kNsPerMs;
    }
  }
}

int Gx1Session::await_reply(std::uint8_t header, Reply& out) {
  const std::int64_t deadline = monotonic_ns() + options_.reply_timeout_ms * kNsPerMs;
  bool found = false;
  for (;;) {
    const std::int64_t now = monotonic_ns();
    if (now >= deadline) return -ETIMEDOUT;
    if (cancelled()) return -ECANCELED;
    const ReadResult r = port_.read_some(
        read_buf_, std::min(static_cast<int>((deadline - now + kNsPerMs - 1) / kNsPerMs), kCancelPollMs));
    if (r.status == ReadStatus::hangup || r.status == ReadStatus::error) return -r.error;
    if (r.status != ReadStatus::data) continue;
    parse(std::span<const std::uint8_t>(read_buf_.data(), r.bytes), [&](const ParsedReply& p) {
      if (!found && header_of(p.reply) == header) {
        out = p.reply;
        found = true;
      }
    });
    if (found) return 0;
  }
}

int Gx1Session::poll_once(int timeout_ms) {
  int n = 0;
  switch (state()) {
    case DeviceState::streaming: n = stream_step(timeout_ms); break;
    case DeviceState::recovering: n = recover_step(timeout_ms); break;
    default: return -ENOTCONN;
  }
  publish_counters();
  return n;
}

int Gx1Session::stream_step(int timeout_ms) {
  if (!options_.continuous && !poll_outstanding_) {
    if (const int rc = send(encode_poll(options_.stream_command)); rc < 0) {
      lose("poll write failed", -rc);
      return 0;
    }
    poll_outstanding_ = true;
    poll_sent_ns_ = monotonic_ns();
  }
  if (poll_outstanding_) {
    const std::int64_t left = poll_sent_ns_ + options_.reply_timeout_ms * kNsPerMs - monotonic_ns();
    timeout_ms = std::clamp(static_cast<int>(left / kNsPerMs), 0, timeout_ms);
  }
  const ReadResult r = port_.read_some(read_buf_, timeout_ms);
  int samples = 0;
  if (r.status == ReadStatus::data) {
    samples = ingest(std::span<const std::uint8_t>(read_buf_.data(), r.bytes), r.t_ns);
  } else if (r.status == ReadStatus::hangup || r.status == ReadStatus::error) {
    lose(r.status == ReadStatus::hangup ? "hang-up" : "read error", r.error);
    return 0;
  }
  const std::int64_t now = monotonic_ns();
  if (poll_outstanding_ && now - poll_sent_ns_ > options_.reply_timeout_ms * kNsPerMs) {
    bump(shared_.poll_timeouts);
    poll_outstanding_ = false;
  }
  if (now - last_sample_ns_ > options_.stream_timeout_ms * kNsPerMs) {
    bump(shared_.stream_timeouts);
    log_to(log_, LogLevel::warning, "gyro", "gx1 %s: no sample for %d ms: reconfiguring", device().c_str(),
           options_.stream_timeout_ms);
    if (const int rc = configure(); rc < 0) lose("reconfiguration failed", -rc);
  }
  return samples;
}

// Stamps each reply with the arrival of its last byte: the read's return time, less the
// wire time of the bytes that came after it in the same read (a backlog read at once).
int Gx1Session::ingest(std::span<const std::uint8_t> bytes, std::int64_t t_read_ns) {
  const std::uint64_t fed_after = parser_.counters().bytes_fed + bytes.size();
  int samples = 0;
  parse(bytes, [&](const ParsedReply& p) {
    const std::int64_t t = t_read_ns - static_cast<std::int64_t>(fed_after - p.end_offset) * SerialPort::kByteTimeNs;
    Gx1Sample s;
    s.t_ns = t;
    if (const auto* e = std::get_if<EulerReply>(&p.reply); e && e->header == options_.stream_command) {
      s.ticks = e->ticks;
      s.angles = {degrees_from_counts(e->roll), degrees_from_counts(e->pitch), degrees_from_counts(e->yaw)};
    } else if (const auto* v = std::get_if<EulerVectorsReply>(&p.reply);
               v && options_.stream_command == cmd::stab_euler_vectors) {
      s.ticks = v->ticks;
      s.angles = {degrees_from_counts(v->roll), degrees_from_counts(v->pitch), degrees_from_counts(v->yaw)};
      const double gain = gyro_gain_scale_.load(std::memory_order_relaxed);
      s.has_rate = true;
      for (std::size_t i = 0; i < 3; ++i) s.rate_radps[i] = rate_rad_s_from_counts(v->rate[i], gain);
    } else if (const auto* a = std::get_if<ContinuousAck>(&p.reply); a && a->streamed() == options_.stream_command) {
      bump(shared_.acks);
      return;
    } else {
      bump(shared_.other_replies);
      return;
    }
    poll_outstanding_ = false;  // the sensor answers: a refused reading is no stall
    last_sample_ns_ = t_read_ns;
    if (options_.vehicle_attitude_only && refuse_implausible(s.angles)) return;
    history_.push(s);
    ++samples;
  });
  bump(shared_.samples, static_cast<std::uint64_t>(samples));
  return samples;
}

bool Gx1Session::refuse_implausible(const Gx1Angles& a) {
  const char* which = implausible_vehicle_angle(a);
  if (!which) return false;
  bump(shared_.refused);
  if (!refusal_reported_) {
    refusal_reported_ = true;
    log_to(log_, LogLevel::warning, "gyro",
           "gx1 %s: refused a reading whose %s no road vehicle can have (roll %.1f, pitch %.1f, yaw %.1f deg; "
           "bounds |roll| <= %.0f, |pitch| <= %.0f deg): the gyro is at fault while only such readings come "
           "(said once)",
           device().c_str(), which, a.roll_deg, a.pitch_deg, a.yaw_deg, kMaxVehicleRollDeg, kMaxVehiclePitchDeg);
  }
  return true;
}

void Gx1Session::lose(const char* what, int error) {
  bump(shared_.hangups);
  log_to(log_, LogLevel::warning, "gyro", "gx1 %s: %s (%s): reopening with backoff", device().c_str(), what,
         std::strerror(error));
  port_.back_off(monotonic_ns());
  parser_.reset();
  reopen_failure_reported_ = false;
  set_state(DeviceState::recovering);
}

int Gx1Session::recover_step(int timeout_ms) {
  const std::int64_t now = monotonic_ns();
  const int rc = port_.reopen_with_backoff(now);
  if (rc == -EAGAIN) {
    sleep_until(std::min(port_.next_attempt_ns(), now + std::int64_t{std::max(timeout_ms, 0)} * kNsPerMs));
    return 0;
  }
  if (rc < 0) {
    if (!reopen_failure_reported_) {
      log_to(log_, LogLevel::warning, "gyro", "gx1 %s: reopen failed: %s (retrying, backoff up to %d ms)",
             device().c_str(), std::strerror(-rc), options_.backoff.max_ms);
      reopen_failure_reported_ = true;
    }
    return 0;
  }
  if (configure() < 0) {
    port_.back_off(monotonic_ns());
    set_state(DeviceState::recovering);
    return 0;
  }
  port_.reset_backoff();
  bump(shared_.reopens);
  log_to(log_, LogLevel::notice, "gyro", "gx1 %s: reopened, streaming again (firmware %u, serial number %u)",
         device().c_str(), unsigned{firmware()}, unsigned{serial_number()});
  return 0;
}

void Gx1Session::publish_counters() {
  const ParserCounters& p = parser_.counters();
  shared_.bad_checksums.store(p.bad_checksums, std::memory_order_relaxed);
  shared_.unconfirmed.store(p.unconfirmed, std::memory_order_relaxed);
  shared_.bytes_skipped.store(p.bytes_skipped, std::memory_order_relaxed);
}

SessionCounters Gx1Session::counters() const {
  const auto get = [](const std::atomic<std::uint64_t>& c) { return c.load(std::memory_order_relaxed); };
  SessionCounters c;
  c.samples = get(shared_.samples);
  c.acks = get(shared_.acks);
  c.other_replies = get(shared_.other_replies);
  c.bad_checksums = get(shared_.bad_checksums);
  c.unconfirmed = get(shared_.unconfirmed);
  c.bytes_skipped = get(shared_.bytes_skipped);
  c.bytes_drained = get(shared_.bytes_drained);
  c.hangups = get(shared_.hangups);
  c.reopens = get(shared_.reopens);
  c.configure_failures = get(shared_.configure_failures);
  c.stream_timeouts = get(shared_.stream_timeouts);
  c.poll_timeouts = get(shared_.poll_timeouts);
  c.refused = get(shared_.refused);
  return c;
}

}  // namespace ccdlane::gx1
