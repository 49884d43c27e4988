// The 3DM-GX1 wire protocol (docs/gx1.md): reply lengths, checksum, decoded replies, scaling,
// command encoders, and the byte-fed reply parser. Pure: never sees an fd, allocates
// nothing, depends only on the standard library (the fuzz target builds it alone).
#pragma once

#include <array>
#include <bitset>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <variant>

namespace ccdlane::gx1 {

// Command bytes (docs/gx1.md section 3). A reply's header echoes its command byte.
namespace cmd {
inline constexpr std::uint8_t raw_sensor = 0x01;
inline constexpr std::uint8_t stab_vectors = 0x02;
inline constexpr std::uint8_t inst_vectors = 0x03;
inline constexpr std::uint8_t inst_quaternion = 0x04;
inline constexpr std::uint8_t stab_quaternion = 0x05;
inline constexpr std::uint8_t capture_bias = 0x06;
inline constexpr std::uint8_t temperature = 0x07;
inline constexpr std::uint8_t inst_matrix = 0x0A;
inline constexpr std::uint8_t stab_matrix = 0x0B;
inline constexpr std::uint8_t stab_quaternion_vectors = 0x0C;
inline constexpr std::uint8_t inst_euler = 0x0D;
inline constexpr std::uint8_t stab_euler = 0x0E;
inline constexpr std::uint8_t tare = 0x0F;
inline constexpr std::uint8_t continuous = 0x10;
inline constexpr std::uint8_t remove_tare = 0x11;
inline constexpr std::uint8_t stab_quaternion_inst_vectors = 0x12;
inline constexpr std::uint8_t write_gains = 0x24;
inline constexpr std::uint8_t read_gains = 0x25;
inline constexpr std::uint8_t self_test = 0x27;
inline constexpr std::uint8_t read_eeprom = 0x28;
inline constexpr std::uint8_t write_eeprom = 0x29;
inline constexpr std::uint8_t stab_euler_vectors = 0x31;
inline constexpr std::uint8_t hard_iron_init = 0x40;
inline constexpr std::uint8_t hard_iron_collect = 0x41;
inline constexpr std::uint8_t hard_iron_compute = 0x42;
inline constexpr std::uint8_t firmware = 0xF0;
inline constexpr std::uint8_t serial_number = 0xF1;
}  // namespace cmd

// Longest reply of the command table (0x0C, 0x12).
inline constexpr std::size_t kMaxReplyLength = 31;

// Total reply length in bytes (header + words + checksum) of `command`, or 0 when the
// command has no framed reply (unknown, or the legacy headerless 0x08/0x09).
std::size_t reply_length(std::uint8_t command);

// Host-to-sensor length of `command` with its parameter bytes (1 for plain polls), or 0
// when unknown. The emulator needs it to split the byte stream it receives.
std::size_t command_length(std::uint8_t command);

// (header zero-extended + sum of the big-endian words) mod 2^16 over `frame`, which is a
// reply without its two checksum bytes (so of odd length).
std::uint16_t checksum(std::span<const std::uint8_t> frame);

// A reply or command on the wire: bytes[0, size).
struct Frame {
  std::array<std::uint8_t, kMaxReplyLength> bytes{};
  std::uint8_t size = 0;
  std::span<const std::uint8_t> span() const { return {bytes.data(), size}; }
};

// ---- decoded replies (raw counts; scaling below) ----------------------------------

// 0x0E gyro-stabilized or 0x0D instantaneous Euler angles.
struct EulerReply {
  std::uint8_t header = cmd::stab_euler;
  std::int16_t roll = 0, pitch = 0, yaw = 0;
  std::uint16_t ticks = 0;
};
// 0x31 gyro-stabilized Euler angles, acceleration and angular rate.
struct EulerVectorsReply {
  std::int16_t roll = 0, pitch = 0, yaw = 0;
  std::array<std::int16_t, 3> accel{}, rate{};
  std::uint16_t ticks = 0;
};
// 0x05 gyro-stabilized or 0x04 instantaneous quaternion; q[0] is the scalar part.
struct QuaternionReply {
  std::uint8_t header = cmd::stab_quaternion;
  std::array<std::int16_t, 4> q{};
  std::uint16_t ticks = 0;
};
struct TemperatureReply {
  std::uint16_t raw = 0;
  std::uint16_t ticks = 0;
};
struct FirmwareReply {
  std::uint16_t number = 0;
};
struct SerialNumberReply {
  std::uint16_t number = 0;
};
// 0x28 read EEPROM with checksum.
struct EepromReply {
  std::uint16_t value = 0;
  std::uint16_t ticks = 0;
};
// 0x10 continuous-mode acknowledgement: word = 0x00CC, CC the streamed command (0 = stop).
struct ContinuousAck {
  std::uint16_t word = 0;
  std::uint16_t ticks = 0;
  std::uint8_t streamed() const { return static_cast<std::uint8_t>(word & 0xFF); }
};
// Any other framed reply, as its words (the last one is usually the ticks).
struct OtherReply {
  std::uint8_t header = 0;
  std::uint8_t word_count = 0;
  std::array<std::uint16_t, (kMaxReplyLength - 3) / 2> words{};
};

using Reply = std::variant<EulerReply, EulerVectorsReply, QuaternionReply, TemperatureReply, FirmwareReply,
                           SerialNumberReply, EepromReply, ContinuousAck, OtherReply>;

// The header byte `reply` goes out with.
std::uint8_t header_of(const Reply& reply);

// Decodes a whole reply whose length and checksum have been checked (parser's job).
Reply decode_reply(std::span<const std::uint8_t> frame);

// The bytes the sensor sends for `reply`, checksum included (emulator, tests, fuzzing).
Frame encode_reply(const Reply& reply);

// ---- command encoders ---------------------------------------------------------------

// A one-byte poll: 0x0E, 0x0D, 0x31, 0x05, 0x04, 0x07, 0xF0, 0xF1 and the other
// commands without parameters.
Frame encode_poll(std::uint8_t command);
// `10 00 CC`: stream replies of `streamed` back to back (docs/gx1.md section 7).
Frame encode_continuous_start(std::uint8_t streamed);
// `10 00 00`: stop streaming.
Frame encode_continuous_stop();
// `28 AH AL`: read one EEPROM word.
Frame encode_eeprom_read(std::uint16_t address);

// ---- scaling (docs/gx1.md section 5) -----------------------------------------------------

inline constexpr double kDegreesPerCount = 360.0 / 65536.0;
inline constexpr double kQuaternionCountsPerUnit = 8192.0;
inline constexpr double kFactoryTickSeconds = 0.0065536;

// EEPROM addresses of the per-unit gain scales, and the fallbacks when they cannot be read.
inline constexpr std::uint16_t kEepromGyroGainScale = 130;
inline constexpr std::uint16_t kEepromAccelGainScale = 230;
inline constexpr std::uint16_t kEepromMagGainScale = 232;
struct GainScales {
  double accel = 7000.0;
  double gyro = 8500.0;
  double mag = 2000.0;
};

constexpr double degrees_from_counts(std::int16_t counts) { return counts * kDegreesPerCount; }
// Nearest count, wrapped into the wire range -180 .. +179.9945 degrees.
std::int16_t counts_from_degrees(double degrees);
constexpr double quaternion_from_counts(std::int16_t counts) { return counts / kQuaternionCountsPerUnit; }
constexpr double accel_g_from_counts(std::int16_t counts, double accel_gain_scale) {
  return counts / (32768000.0 / accel_gain_scale);
}
constexpr double rate_rad_s_from_counts(std::int16_t counts, double gyro_gain_scale) {
  return counts / (32768000.0 / gyro_gain_scale);
}
constexpr double mag_gauss_from_counts(std::int16_t counts, double mag_gain_scale) {
  return counts / (32768000.0 / mag_gain_scale);
}
constexpr double temperature_c_from_counts(std::uint16_t raw) { return ((raw * 5.0 / 65536.0) - 0.5) * 100.0; }
// Ticks elapsed from `earlier` to `later`, across the 16-bit wrap.
constexpr std::uint16_t tick_delta(std::uint16_t later, std::uint16_t earlier) {
  return static_cast<std::uint16_t>(later - earlier);
}

// Firmware number n as major.minor.build: 3102 -> 3, 1, 2 (printed "3.1.02").
struct FirmwareVersion {
  int major = 0, minor = 0, build = 0;
};
constexpr FirmwareVersion firmware_version(std::uint16_t n) { return {n / 1000, (n % 1000) / 100, n % 100}; }

// ---- the parser ---------------------------------------------------------------------

// A reply found in the byte stream. `end_offset` counts every byte ever fed up to and
// including the reply's last byte, so a caller that knows when a read returned can say
// when that byte arrived.
struct ParsedReply {
  Reply reply;
  std::uint64_t end_offset = 0;
};

struct ParserCounters {
  std::uint64_t bytes_fed = 0;
  std::uint64_t replies = 0;        // accepted replies
  std::uint64_t bad_checksums = 0;  // candidate positions (expected header, enough bytes) that failed the sum
  std::uint64_t unconfirmed = 0;    // checksum passed while resynchronising but no header followed
  std::uint64_t bytes_skipped = 0;  // bytes discarded while searching for a reply
};

// Frames replies out of a byte stream (docs/gx1.md section 7). The header byte is the only
// sync mark and occurs inside data, so the parser slides: at each position holding an
// expected header with a whole reply's worth of bytes it checks the checksum, consumes
// the reply on success and advances ONE byte on failure.
//
// Extra check (docs/gx1.md section 7 recommends one): after bytes have been skipped, a
// candidate is accepted only when another expected header byte follows right after it.
// Lost sync is when false matches happen (a 16-bit sum passes by chance for 1 offset
// in 65536 tried); the check cuts that by a further ~256 in a continuous stream, where the
// next reply always follows. Its cost: a reply found during resync is delivered one
// byte later, and one whose follower is also damaged is dropped (two faults within one
// reply). Turn it off (confirm_resync(false)) for single polled replies, which have no
// follower. In sync (after reset(), or right after an accepted reply) nothing changes.
// Ticks are not used as a check: their period depends on EEPROM settings (section 6).
class ReplyParser {
 public:
  // Twice the longest decision window (31 + 1 bytes), so a stalled parser can always take more.
  static constexpr std::size_t kCapacity = 64;

  ReplyParser();

  // The headers to look for (any with a framed reply). Default: every reply type that
  // has its own struct above. Narrowing it (e.g. to 0x10 and 0x0E while streaming)
  // makes false matches rarer still.
  void expect(std::initializer_list<std::uint8_t> headers);
  void expect_default();
  void confirm_resync(bool on) { confirm_resync_ = on; }

  // Copies as many of `bytes` as fit and returns how many it took. Call next() until it
  // returns false, then feed the rest: after next() has returned false at least 32 bytes fit.
  std::size_t feed(std::span<const std::uint8_t> bytes);

  // The next reply, if the buffered bytes hold one; false when more bytes are needed.
  bool next(ParsedReply& out);

  // Forgets buffered bytes (after tcflush) and counts them as skipped; back in sync.
  void reset();

  std::size_t buffered() const { return end_ - begin_; }
  const ParserCounters& counters() const { return counters_; }

 private:
  void skip(std::size_t n);

  std::array<std::uint8_t, kCapacity> buf_{};
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  std::bitset<256> expected_;
  bool confirm_resync_ = true;
  bool in_sync_ = true;
  ParserCounters counters_;
};

}  // namespace ccdlane::gx1
