// The 3DM-GX1 wire protocol: tables from docs/gx1.md section 3, checksum from section 2, the
// sliding-window parser from section 7.
#include "drivers/gx1/gx1_protocol.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

namespace ccdlane::gx1 {
namespace {

std::uint16_t word_at(std::span<const std::uint8_t> frame, std::size_t index) {
  return static_cast<std::uint16_t>((frame[1 + 2 * index] << 8) | frame[2 + 2 * index]);
}

std::int16_t signed_word_at(std::span<const std::uint8_t> frame, std::size_t index) {
  return static_cast<std::int16_t>(word_at(frame, index));
}

// Builds a reply: header, words, then the checksum.
class FrameWriter {
 public:
  explicit FrameWriter(std::uint8_t header) { frame_.bytes[frame_.size++] = header; }
  FrameWriter& word(std::uint16_t w) {
    frame_.bytes[frame_.size++] = static_cast<std::uint8_t>(w >> 8);
    frame_.bytes[frame_.size++] = static_cast<std::uint8_t>(w & 0xFF);
    return *this;
  }
  FrameWriter& word(std::int16_t w) { return word(static_cast<std::uint16_t>(w)); }
  Frame finish() {
    word(checksum(frame_.span()));
    return frame_;
  }

 private:
  Frame frame_;
};

Frame bytes_frame(std::initializer_list<std::uint8_t> bytes) {
  Frame f;
  for (std::uint8_t b : bytes) f.bytes[f.size++] = b;
  return f;
}

}  // namespace

std::size_t reply_length(std::uint8_t command) {
  switch (command) {
    case cmd::raw_sensor:
    case cmd::stab_vectors:
    case cmd::inst_vectors:
    case cmd::inst_matrix:
    case cmd::stab_matrix:
    case cmd::stab_euler_vectors:
    case cmd::hard_iron_collect: return 23;
    case cmd::inst_quaternion:
    case cmd::stab_quaternion: return 13;
    case cmd::capture_bias:
    case cmd::tare:
    case cmd::remove_tare:
    case cmd::write_gains:
    case cmd::self_test:
    case cmd::hard_iron_init:
    case cmd::firmware:
    case cmd::serial_number: return 5;
    case cmd::temperature:
    case cmd::continuous:
    case cmd::read_eeprom:
    case cmd::write_eeprom: return 7;
    case cmd::stab_quaternion_vectors:
    case cmd::stab_quaternion_inst_vectors: return 31;
    case cmd::inst_euler:
    case cmd::stab_euler:
    case cmd::read_gains:
    case cmd::hard_iron_compute: return 11;
    default: return 0;
  }
}

std::size_t command_length(std::uint8_t command) {
  switch (command) {
    case 0x08:  // legacy read EEPROM: 08 ad
      return 2;
    case cmd::continuous:
    case cmd::read_eeprom:
    case cmd::hard_iron_init: return 3;
    case cmd::tare:
    case cmd::remove_tare: return 4;
    case 0x09:  // legacy write EEPROM: 09 71 ad VH VL AA
    case cmd::hard_iron_compute: return 6;
    case cmd::write_gains:
    case cmd::write_eeprom: return 7;
    default: return reply_length(command) != 0 ? 1 : 0;
  }
}

std::uint16_t checksum(std::span<const std::uint8_t> frame) {
  assert(!frame.empty() && frame.size() % 2 == 1);
  // Zero-extended header and uint16 arithmetic: sign-extending a char header breaks
  // 0xF0/0xF1 (docs/gx1.md section 9.6).
  std::uint32_t sum = frame[0];
  for (std::size_t i = 1; i + 1 < frame.size(); i += 2)
    sum += static_cast<std::uint32_t>((frame[i] << 8) | frame[i + 1]);
  return static_cast<std::uint16_t>(sum & 0xFFFF);
}

std::uint8_t header_of(const Reply& reply) {
  struct Visitor {
    std::uint8_t operator()(const EulerReply& r) const { return r.header; }
    std::uint8_t operator()(const EulerVectorsReply&) const { return cmd::stab_euler_vectors; }
    std::uint8_t operator()(const QuaternionReply& r) const { return r.header; }
    std::uint8_t operator()(const TemperatureReply&) const { return cmd::temperature; }
    std::uint8_t operator()(const FirmwareReply&) const { return cmd::firmware; }
    std::uint8_t operator()(const SerialNumberReply&) const { return cmd::serial_number; }
    std::uint8_t operator()(const EepromReply&) const { return cmd::read_eeprom; }
    std::uint8_t operator()(const ContinuousAck&) const { return cmd::continuous; }
    std::uint8_t operator()(const OtherReply& r) const { return r.header; }
  };
  return std::visit(Visitor{}, reply);
}

Reply decode_reply(std::span<const std::uint8_t> frame) {
  assert(!frame.empty() && frame.size() == reply_length(frame[0]));
  const std::uint8_t header = frame[0];
  switch (header) {
    case cmd::stab_euler:
    case cmd::inst_euler:
      return EulerReply{header, signed_word_at(frame, 0), signed_word_at(frame, 1), signed_word_at(frame, 2),
                        word_at(frame, 3)};
    case cmd::stab_euler_vectors: {
      EulerVectorsReply r;
      r.roll = signed_word_at(frame, 0);
      r.pitch = signed_word_at(frame, 1);
      r.yaw = signed_word_at(frame, 2);
      for (std::size_t i = 0; i < 3; ++i) {
        r.accel[i] = signed_word_at(frame, 3 + i);
        r.rate[i] = signed_word_at(frame, 6 + i);
      }
      r.ticks = word_at(frame, 9);
      return r;
    }
    case cmd::stab_quaternion:
    case cmd::inst_quaternion: {
      QuaternionReply r;
      r.header = header;
      for (std::size_t i = 0; i < 4; ++i) r.q[i] = signed_word_at(frame, i);
      r.ticks = word_at(frame, 4);
      return r;
    }
    case cmd::temperature: return TemperatureReply{word_at(frame, 0), word_at(frame, 1)};
    case cmd::firmware: return FirmwareReply{word_at(frame, 0)};
    case cmd::serial_number: return SerialNumberReply{word_at(frame, 0)};
    case cmd::read_eeprom: return EepromReply{word_at(frame, 0), word_at(frame, 1)};
    case cmd::continuous: return ContinuousAck{word_at(frame, 0), word_at(frame, 1)};
    default: {
      OtherReply r;
      r.header = header;
      r.word_count = static_cast<std::uint8_t>((frame.size() - 3) / 2);
      for (std::size_t i = 0; i < r.word_count; ++i) r.words[i] = word_at(frame, i);
      return r;
    }
  }
}

Frame encode_reply(const Reply& reply) {
  struct Visitor {
    Frame operator()(const EulerReply& r) const {
      return FrameWriter(r.header).word(r.roll).word(r.pitch).word(r.yaw).word(r.ticks).finish();
    }
    Frame operator()(const EulerVectorsReply& r) const {
      FrameWriter w(cmd::stab_euler_vectors);
      w.word(r.roll).word(r.pitch).word(r.yaw);
      for (std::int16_t a : r.accel) w.word(a);
      for (std::int16_t g : r.rate) w.word(g);
      return w.word(r.ticks).finish();
    }
    Frame operator()(const QuaternionReply& r) const {
      FrameWriter w(r.header);
      for (std::int16_t q : r.q) w.word(q);
      return w.word(r.ticks).finish();
    }
    Frame operator()(const TemperatureReply& r) const {
      return FrameWriter(cmd::temperature).word(r.raw).word(r.ticks).finish();
    }
    Frame operator()(const FirmwareReply& r) const { return FrameWriter(cmd::firmware).word(r.number).finish(); }
    Frame operator()(const SerialNumberReply& r) const {
      return FrameWriter(cmd::serial_number).word(r.number).finish();
    }
    Frame operator()(const EepromReply& r) const {
      return FrameWriter(cmd::read_eeprom).word(r.value).word(r.ticks).finish();
    }
    Frame operator()(const ContinuousAck& r) const {
      return FrameWriter(cmd::continuous).word(r.word).word(r.ticks).finish();
    }
    Frame operator()(const OtherReply& r) const {
      FrameWriter w(r.header);
      for (std::size_t i = 0; i < r.word_count; ++i) w.word(r.words[i]);
      return w.finish();
    }
  };
  return std::visit(Visitor{}, reply);
}

Frame encode_poll(std::uint8_t command) {
  assert(command_length(command) == 1);
  return bytes_frame({command});
}

Frame encode_continuous_start(std::uint8_t streamed) { return bytes_frame({cmd::continuous, 0x00, streamed}); }

Frame encode_continuous_stop() { return bytes_frame({cmd::continuous, 0x00, 0x00}); }

Frame encode_eeprom_read(std::uint16_t address) {
  return bytes_frame(
      {cmd::read_eeprom, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address & 0xFF)});
}

std::int16_t counts_from_degrees(double degrees) {
  const double wrapped = std::remainder(degrees, 360.0);  // [-180, 180]
  long counts = std::lround(wrapped / kDegreesPerCount);
  if (counts >= 32768) counts -= 65536;  // +180 is -180 on the wire
  return static_cast<std::int16_t>(counts);
}

// ---- ReplyParser ----------------------------------------------------------------------

ReplyParser::ReplyParser() { expect_default(); }

void ReplyParser::expect(std::initializer_list<std::uint8_t> headers) {
  expected_.reset();
  for (std::uint8_t h : headers) {
    assert(reply_length(h) != 0);
    expected_.set(h);
  }
}

void ReplyParser::expect_default() {
  expect({cmd::stab_euler, cmd::inst_euler, cmd::stab_euler_vectors, cmd::stab_quaternion, cmd::inst_quaternion,
          cmd::temperature, cmd::firmware, cmd::serial_number, cmd::read_eeprom, cmd::continuous});
}

std::size_t ReplyParser::feed(std::span<const std::uint8_t> bytes) {
  if (begin_ > 0) {  // at most kCapacity bytes move: cheaper than a ring's split copies
    std::memmove(buf_.data(), buf_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  const std::size_t n = std::min(bytes.size(), kCapacity - end_);
  if (n > 0) std::memcpy(buf_.data() + end_, bytes.data(), n);
  end_ += n;
  counters_.bytes_fed += n;
  return n;
}

bool ReplyParser::next(ParsedReply& out) {
  while (begin_ < end_) {
    const std::uint8_t header = buf_[begin_];
    const std::size_t length = expected_.test(header) ? reply_length(header) : 0;
    if (length == 0) {
      skip(1);
      continue;
    }
    const bool confirm = confirm_resync_ && !in_sync_;
    if (end_ - begin_ < length + (confirm ? 1 : 0)) return false;  // wait for more bytes
    const std::span<const std::uint8_t> frame(buf_.data() + begin_, length);
    const std::uint16_t sent = static_cast<std::uint16_t>((frame[length - 2] << 8) | frame[length - 1]);
    if (checksum(frame.first(length - 2)) != sent) {
      ++counters_.bad_checksums;
      skip(1);
      continue;
    }
    if (confirm && !expected_.test(buf_[begin_ + length])) {
      ++counters_.unconfirmed;
      skip(1);
      continue;
    }
    out.reply = decode_reply(frame);
    begin_ += length;
    out.end_offset = counters_.bytes_fed - (end_ - begin_);
    ++counters_.replies;
    in_sync_ = true;
    return true;
  }
  return false;
}

void ReplyParser::reset() {
  counters_.bytes_skipped += end_ - begin_;
  begin_ = end_ = 0;
  in_sync_ = true;
}

void ReplyParser::skip(std::size_t n) {
  begin_ += n;
  counters_.bytes_skipped += n;
  in_sync_ = false;
}

}  // namespace ccdlane::gx1
