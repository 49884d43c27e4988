// The 3DM-GX1 protocol layer against docs/gx1.md section 10 (every vector decoded exactly),
// the sliding-window resynchronisation of section 7, and the command encoders.
#include "drivers/gx1/gx1_protocol.hpp"

#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane::gx1 {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes hex(const std::string& text) {
  Bytes out;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    out.push_back(static_cast<std::uint8_t>(std::stoul(text.substr(i, 2), nullptr, 16)));
    i += 2;
  }
  return out;
}

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

Bytes bytes_of(const Frame& f) { return {f.bytes.begin(), f.bytes.begin() + f.size}; }

// Feeds `stream` in chunks of `chunk` bytes (0: all at once), collecting every reply.
std::vector<ParsedReply> parse_all(ReplyParser& parser, const Bytes& stream, std::size_t chunk = 0) {
  std::vector<ParsedReply> out;
  std::span<const std::uint8_t> rest(stream);
  ParsedReply r;
  while (!rest.empty()) {
    const std::size_t n = chunk == 0 ? rest.size() : std::min(chunk, rest.size());
    std::span<const std::uint8_t> piece = rest.first(n);
    rest = rest.subspan(n);
    while (!piece.empty()) {
      piece = piece.subspan(parser.feed(piece));
      while (parser.next(r)) out.push_back(r);
    }
  }
  return out;
}

std::vector<ParsedReply> parse_all(const Bytes& stream, std::size_t chunk = 0) {
  ReplyParser parser;
  return parse_all(parser, stream, chunk);
}

const Bytes kV1 = hex("0E 00 00 E0 00 40 00 12 34 32 42");
const Bytes kV2 = hex("0E 01 00 FF 00 80 00 FF FF 80 0D");
const Bytes kV3 = hex("31 15 55 F8 89 60 00 00 00 00 00 ED B7 01 82 00 00 FE 7E 0A 0B 65 D1");
const Bytes kV4 = hex("07 26 66 01 00 27 6D");
const Bytes kV5Firmware = hex("F0 0C 1E 0D 0E");
const Bytes kV5Serial = hex("F1 04 D2 05 C3");
const Bytes kV6Ack = hex("10 00 0E 00 01 00 1F");
const Bytes kV7 = hex("28 21 34 02 00 23 5C");
const Bytes kV8 = hex("55 AA 00 00 00 00 0E 1C 0E 0E 0E 00 00 00 00 00 00 0E 1C 0E 0E 0E 00 00 00 00 00 00 0E 1C");

template <typename T>
T single_reply(const Bytes& frame) {
  ReplyParser parser;
  const auto replies = parse_all(parser, frame);
  EXPECT_EQ(replies.size(), 1u);
  EXPECT_EQ(parser.counters().bytes_skipped, 0u);
  EXPECT_EQ(parser.counters().bad_checksums, 0u);
  if (replies.size() != 1 || !std::holds_alternative<T>(replies[0].reply)) {
    ADD_FAILURE() << "not decoded as the expected reply type";
    return T{};
  }
  EXPECT_EQ(replies[0].end_offset, frame.size());
  EXPECT_EQ(bytes_of(encode_reply(replies[0].reply)), frame) << "re-encoding differs";
  return std::get<T>(replies[0].reply);
}

TEST(Gx1Protocol, V1EulerSimpleAngles) {
  const EulerReply r = single_reply<EulerReply>(kV1);
  EXPECT_EQ(r.header, cmd::stab_euler);
  EXPECT_EQ(r.roll, 0);
  EXPECT_EQ(r.pitch, -8192);
  EXPECT_EQ(r.yaw, 16384);
  EXPECT_EQ(r.ticks, 4660);
  EXPECT_EQ(degrees_from_counts(r.roll), 0.0);
  EXPECT_EQ(degrees_from_counts(r.pitch), -45.0);
  EXPECT_EQ(degrees_from_counts(r.yaw), 90.0);
  EXPECT_NEAR(r.ticks * kFactoryTickSeconds, 30.539776, 5e-7);
  EXPECT_EQ(checksum(std::span(kV1).first(9)), 0x3242);
}

TEST(Gx1Protocol, V2SignEdgesAndChecksumWrap) {
  const EulerReply r = single_reply<EulerReply>(kV2);
  EXPECT_EQ(r.roll, 256);
  EXPECT_EQ(r.pitch, -256);
  EXPECT_EQ(r.yaw, -32768);
  EXPECT_EQ(r.ticks, 65535);
  EXPECT_EQ(degrees_from_counts(r.roll), 1.40625);
  EXPECT_EQ(degrees_from_counts(r.pitch), -1.40625);
  EXPECT_EQ(degrees_from_counts(r.yaw), -180.0);
  EXPECT_NEAR(r.ticks * kFactoryTickSeconds, 429.490176, 5e-7);
  EXPECT_EQ(tick_delta(0, r.ticks), 1);  // the next tick wraps to 0
}

TEST(Gx1Protocol, V3EulerAccelRateWithDefaultGains) {
  const EulerVectorsReply r = single_reply<EulerVectorsReply>(kV3);
  EXPECT_EQ(r.roll, 5461);
  EXPECT_EQ(r.pitch, -1911);
  EXPECT_EQ(r.yaw, 24576);
  EXPECT_EQ(r.accel, (std::array<std::int16_t, 3>{0, 0, -4681}));
  EXPECT_EQ(r.rate, (std::array<std::int16_t, 3>{386, 0, -386}));
  EXPECT_EQ(r.ticks, 2571);
  EXPECT_NEAR(degrees_from_counts(r.roll), 29.998169, 5e-7);
  EXPECT_NEAR(degrees_from_counts(r.pitch), -10.497437, 5e-7);
  EXPECT_EQ(degrees_from_counts(r.yaw), 135.0);
  const GainScales gains;
  EXPECT_EQ(accel_g_from_counts(r.accel[0], gains.accel), 0.0);
  EXPECT_NEAR(accel_g_from_counts(r.accel[2], gains.accel), -0.999969, 5e-7);
  EXPECT_NEAR(rate_rad_s_from_counts(r.rate[0], gains.gyro), 0.100128, 5e-7);
  EXPECT_NEAR(rate_rad_s_from_counts(r.rate[2], gains.gyro), -0.100128, 5e-7);
  EXPECT_NEAR(r.ticks * kFactoryTickSeconds, 16.849306, 5e-7);
}

TEST(Gx1Protocol, V4Temperature) {
  const TemperatureReply r = single_reply<TemperatureReply>(kV4);
  EXPECT_EQ(r.raw, 0x2666);
  EXPECT_EQ(r.ticks, 0x0100);
  EXPECT_NEAR(temperature_c_from_counts(r.raw), 24.996948, 5e-7);
  EXPECT_NEAR(r.ticks * kFactoryTickSeconds, 1.677722, 5e-7);
}

TEST(Gx1Protocol, V5FirmwareAndSerialNumberHaveZeroExtendedHeaders) {
  const FirmwareReply f = single_reply<FirmwareReply>(kV5Firmware);
  EXPECT_EQ(f.number, 3102);
  const FirmwareVersion v = firmware_version(f.number);
  EXPECT_EQ(v.major, 3);
  EXPECT_EQ(v.minor, 1);
  EXPECT_EQ(v.build, 2);
  EXPECT_EQ(single_reply<SerialNumberReply>(kV5Serial).number, 1234);
  // A sign-extended 0xF0 header would give 0x0C0E (docs/gx1.md section 9.6).
  EXPECT_EQ(checksum(std::span(kV5Firmware).first(3)), 0x0D0E);
}

TEST(Gx1Protocol, V6ContinuousHandshake) {
  EXPECT_EQ(bytes_of(encode_continuous_start(cmd::stab_euler)), hex("10 00 0E"));
  const ContinuousAck ack = single_reply<ContinuousAck>(kV6Ack);
  EXPECT_EQ(ack.word, 0x000E);
  EXPECT_EQ(ack.streamed(), cmd::stab_euler);
  EXPECT_EQ(ack.ticks, 1);
  EXPECT_EQ(bytes_of(encode_continuous_stop()), hex("10 00 00"));
}

TEST(Gx1Protocol, V7EepromGyroGain) {
  EXPECT_EQ(bytes_of(encode_eeprom_read(kEepromGyroGainScale)), hex("28 00 82"));
  const EepromReply r = single_reply<EepromReply>(kV7);
  EXPECT_EQ(r.value, 8500);
  EXPECT_EQ(r.ticks, 0x0200);
}

TEST(Gx1Protocol, V8YieldsExactlyItsTwoPackets) {
  for (const bool confirm : {true, false}) {
    for (const std::size_t chunk : {std::size_t{0}, std::size_t{1}, std::size_t{3}}) {
      SCOPED_TRACE(testing::Message() << "confirm " << confirm << " chunk " << chunk);
      ReplyParser parser;
      parser.confirm_resync(confirm);
      const auto replies = parse_all(parser, kV8, chunk);
      ASSERT_EQ(replies.size(), 2u);
      EXPECT_EQ(replies[0].end_offset, 8u + 11u);   // the packet starting at 8
      EXPECT_EQ(replies[1].end_offset, 19u + 11u);  // and at 19
      for (const ParsedReply& p : replies) {
        const EulerReply& e = std::get<EulerReply>(p.reply);
        EXPECT_EQ(e.roll, 0x0E0E);
        EXPECT_NEAR(degrees_from_counts(e.roll), 19.764404, 5e-7);
        EXPECT_EQ(e.pitch, 0);
        EXPECT_EQ(e.yaw, 0);
        EXPECT_EQ(e.ticks, 0);
      }
      // Bytes 0-7 discarded (one failed checksum, at 6); the false headers at 9, 10,
      // 17, 20, 21 and 28 lie inside accepted packets and are never tried.
      EXPECT_EQ(parser.counters().bytes_skipped, 8u);
      EXPECT_EQ(parser.counters().bad_checksums, 1u);
      EXPECT_EQ(parser.buffered(), 0u);
    }
  }
}

TEST(Gx1Protocol, SkippingAWholePacketLengthAfterAFailureWouldLoseV8) {
  // The counter-example of docs/gx1.md section 10, checked so the test above means something:
  // jumping 11 bytes from the false header at 6 lands on 17, then 28, missing both packets.
  ASSERT_EQ(kV8[6], cmd::stab_euler);
  EXPECT_NE(checksum(std::span(kV8).subspan(6, 9)), (kV8[15] << 8 | kV8[16]));
  EXPECT_NE(checksum(std::span(kV8).subspan(17, 9)), (kV8[26] << 8 | kV8[27]));
}

TEST(Gx1Protocol, GarbageThenRecovers) {
  std::mt19937 rng(7);
  Bytes garbage(200);
  for (auto& b : garbage) b = static_cast<std::uint8_t>(rng());
  // Plenty of false headers, and a truncated real packet right before the good ones.
  for (std::size_t i = 0; i < garbage.size(); i += 9) garbage[i] = cmd::stab_euler;
  const Bytes stream = concat({garbage, Bytes(kV1.begin(), kV1.begin() + 6), kV1, kV2, kV1});
  ReplyParser parser;
  const auto replies = parse_all(parser, stream);
  ASSERT_EQ(replies.size(), 3u);
  EXPECT_EQ(bytes_of(encode_reply(replies[0].reply)), kV1);
  EXPECT_EQ(bytes_of(encode_reply(replies[1].reply)), kV2);
  EXPECT_EQ(bytes_of(encode_reply(replies[2].reply)), kV1);
  EXPECT_EQ(parser.counters().bytes_skipped, garbage.size() + 6);
  EXPECT_GT(parser.counters().bad_checksums, 20u);
}

TEST(Gx1Protocol, EverySingleBitFlipIsRejectedAndTheStreamGoesOn) {
  for (std::size_t bit = 0; bit < kV1.size() * 8; ++bit) {
    Bytes damaged = kV1;
    damaged[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    const auto replies = parse_all(concat({kV2, damaged, kV2, kV1}));
    ASSERT_EQ(replies.size(), 3u) << "bit " << bit;
    EXPECT_EQ(bytes_of(encode_reply(replies[0].reply)), kV2);
    EXPECT_EQ(bytes_of(encode_reply(replies[1].reply)), kV2) << "bit " << bit;
    EXPECT_EQ(bytes_of(encode_reply(replies[2].reply)), kV1);
  }
}

TEST(Gx1Protocol, ChunkingNeverChangesTheResult) {
  std::mt19937 rng(11);
  Bytes stream;
  for (int i = 0; i < 300; ++i) {
    if (rng() % 4 == 0)
      for (auto j = rng() % 13; j > 0; --j) stream.push_back(static_cast<std::uint8_t>(rng()));
    EulerReply e{cmd::stab_euler, static_cast<std::int16_t>(rng()), static_cast<std::int16_t>(rng()),
                 static_cast<std::int16_t>(rng()), static_cast<std::uint16_t>(i)};
    const Bytes p = bytes_of(encode_reply(e));
    stream.insert(stream.end(), p.begin(), p.end());
  }
  const auto whole = parse_all(stream);
  // Packets with garbage on both sides may go (the confirmation's cost); most arrive.
  EXPECT_GT(whole.size(), 250u);
  for (const std::size_t chunk : {1, 2, 5, 11, 17, 64}) {
    const auto pieces = parse_all(stream, chunk);
    ASSERT_EQ(pieces.size(), whole.size()) << "chunk " << chunk;
    for (std::size_t i = 0; i < whole.size(); ++i) {
      EXPECT_EQ(pieces[i].end_offset, whole[i].end_offset);
      EXPECT_EQ(bytes_of(encode_reply(pieces[i].reply)), bytes_of(encode_reply(whole[i].reply)));
    }
  }
}

TEST(Gx1Protocol, ResyncConfirmationCostsAPacketSurroundedByGarbage) {
  // The documented price of the extra check: a packet found while resynchronising whose
  // follower is damaged too is dropped with confirmation, kept without.
  const Bytes junk = hex("55 AA 01");
  const Bytes stream = concat({junk, kV1, junk, kV2, kV1});
  ReplyParser confirming;
  EXPECT_EQ(parse_all(confirming, stream).size(), 2u);
  EXPECT_EQ(confirming.counters().unconfirmed, 1u);
  ReplyParser trusting;
  trusting.confirm_resync(false);
  EXPECT_EQ(parse_all(trusting, stream).size(), 3u);
}

TEST(Gx1Protocol, OnlyExpectedHeadersAreFramed) {
  ReplyParser parser;
  parser.expect({cmd::stab_euler});
  const auto replies = parse_all(parser, concat({kV5Firmware, kV1, kV1}));
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(parser.counters().bytes_skipped, kV5Firmware.size());
}

TEST(Gx1Protocol, FramesUnmodelledRepliesAsWords) {
  ReplyParser parser;
  parser.expect({cmd::stab_matrix});
  OtherReply m;
  m.header = cmd::stab_matrix;
  m.word_count = 10;
  for (std::uint16_t i = 0; i < 10; ++i) m.words[i] = static_cast<std::uint16_t>(0x1000 * i + 0x81);
  const Bytes frame = bytes_of(encode_reply(m));
  ASSERT_EQ(frame.size(), reply_length(cmd::stab_matrix));
  const auto replies = parse_all(parser, frame);
  ASSERT_EQ(replies.size(), 1u);
  const auto& o = std::get<OtherReply>(replies[0].reply);
  EXPECT_EQ(o.word_count, 10);
  EXPECT_EQ(o.words, m.words);
}

TEST(Gx1Protocol, NeverStallsOnEndlessNoise) {
  ReplyParser parser;
  const Bytes noise(5000, cmd::stab_euler);  // every byte a header, every checksum wrong
  const auto replies = parse_all(parser, noise, 7);
  EXPECT_TRUE(replies.empty());
  const ParserCounters& c = parser.counters();
  EXPECT_EQ(c.bytes_fed, noise.size());
  EXPECT_EQ(c.bytes_skipped + parser.buffered(), noise.size());
  EXPECT_LT(parser.buffered(), kMaxReplyLength + 1);
}

TEST(Gx1Protocol, ResetDropsBufferedBytesAndResyncs) {
  ReplyParser parser;
  ParsedReply r;
  parser.feed(std::span(kV1).first(5));
  EXPECT_FALSE(parser.next(r));
  parser.reset();
  EXPECT_EQ(parser.buffered(), 0u);
  EXPECT_EQ(parser.counters().bytes_skipped, 5u);
  parser.feed(kV2);
  ASSERT_TRUE(parser.next(r));  // in sync again: no follower needed
  EXPECT_EQ(std::get<EulerReply>(r.reply).roll, 256);
}

TEST(Gx1Protocol, ReplyAndCommandLengths) {
  EXPECT_EQ(reply_length(cmd::stab_euler), 11u);
  EXPECT_EQ(reply_length(cmd::inst_euler), 11u);
  EXPECT_EQ(reply_length(cmd::stab_euler_vectors), 23u);
  EXPECT_EQ(reply_length(cmd::stab_quaternion), 13u);
  EXPECT_EQ(reply_length(cmd::temperature), 7u);
  EXPECT_EQ(reply_length(cmd::firmware), 5u);
  EXPECT_EQ(reply_length(cmd::serial_number), 5u);
  EXPECT_EQ(reply_length(cmd::read_eeprom), 7u);
  EXPECT_EQ(reply_length(cmd::continuous), 7u);
  EXPECT_EQ(reply_length(cmd::stab_quaternion_vectors), kMaxReplyLength);
  EXPECT_EQ(reply_length(0x08), 0u);  // legacy EEPROM read: no header, not framed
  EXPECT_EQ(reply_length(0x55), 0u);
  for (int c = 0; c < 256; ++c) {
    const std::size_t n = reply_length(static_cast<std::uint8_t>(c));
    EXPECT_TRUE(n == 0 || (n % 2 == 1 && n >= 5 && n <= kMaxReplyLength)) << c;
  }
  EXPECT_EQ(command_length(cmd::stab_euler), 1u);
  EXPECT_EQ(command_length(cmd::continuous), 3u);
  EXPECT_EQ(command_length(cmd::read_eeprom), 3u);
  EXPECT_EQ(command_length(cmd::write_eeprom), 7u);
  EXPECT_EQ(command_length(0x55), 0u);
}

TEST(Gx1Protocol, PollEncoders) {
  for (const std::uint8_t c : {cmd::stab_euler, cmd::stab_euler_vectors, cmd::stab_quaternion, cmd::temperature,
                               cmd::firmware, cmd::serial_number})
    EXPECT_EQ(bytes_of(encode_poll(c)), Bytes{c});
}

TEST(Gx1Protocol, DegreesToCountsRoundTripsEveryCount) {
  for (int c = -32768; c <= 32767; ++c)
    ASSERT_EQ(counts_from_degrees(degrees_from_counts(static_cast<std::int16_t>(c))), c);
  EXPECT_EQ(counts_from_degrees(180.0), -32768);
  EXPECT_EQ(counts_from_degrees(-180.0), -32768);
  EXPECT_EQ(counts_from_degrees(179.999), -32768);  // nearer +180 = -180
  EXPECT_EQ(counts_from_degrees(270.0), -16384);
  EXPECT_EQ(counts_from_degrees(-45.0), -8192);
}

TEST(Gx1Protocol, QuaternionScaling) {
  QuaternionReply q;
  q.q = {8192, -4096, 0, 1};
  q.ticks = 9;
  const Bytes frame = bytes_of(encode_reply(q));
  ASSERT_EQ(frame.size(), 13u);
  const QuaternionReply back = single_reply<QuaternionReply>(frame);
  EXPECT_EQ(back.q, q.q);
  EXPECT_EQ(quaternion_from_counts(back.q[0]), 1.0);
  EXPECT_EQ(quaternion_from_counts(back.q[1]), -0.5);
}

}  // namespace
}  // namespace ccdlane::gx1
