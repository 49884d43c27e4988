// The emulator as a raw peer on its pty (no session): it must answer like docs/gx1.md says
// the sensor does, stream at its own pace, and disappear/reappear behind its link.
#include "drivers/gx1/gx1_emulator.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/device_state.hpp"
#include "drivers/gx1/serial_port.hpp"
#include "tests/drivers/gx1/sent_packets_check.hpp"

namespace ccdlane::gx1 {
namespace {

constexpr Gx1Angles kFixed{12.5, -3.25, 179.99};

EmulatorOptions fixed_attitude() {
  EmulatorOptions o;
  o.attitude = [](double) { return kFixed; };
  return o;
}

// Talks to the emulator through the real transport and parser.
struct Host {
  SerialPort port;
  ReplyParser parser;
  explicit Host(const std::string& path) : port(path) { EXPECT_EQ(port.open(), 0); }

  void send(const Frame& f) { ASSERT_EQ(port.write_all(f.span(), 500), 0); }

  // Every reply that arrives within `ms`.
  std::vector<Reply> collect(int ms) {
    std::vector<Reply> out;
    const std::int64_t end = monotonic_ns() + std::int64_t{ms} * 1'000'000;
    std::uint8_t buf[512];
    while (monotonic_ns() < end) {
      const ReadResult r = port.read_some(buf, 10);
      if (r.status != ReadStatus::data) continue;
      std::span<const std::uint8_t> rest(buf, r.bytes);
      ParsedReply p;
      while (!rest.empty()) {
        rest = rest.subspan(parser.feed(rest));
        while (parser.next(p)) out.push_back(p.reply);
      }
    }
    return out;
  }
  template <typename T>
  T ask(const Frame& command) {
    send(command);
    const auto replies = collect(100);
    EXPECT_EQ(replies.size(), 1u);
    if (replies.size() != 1 || !std::holds_alternative<T>(replies[0])) {
      ADD_FAILURE() << "no single reply of the expected type";
      return T{};
    }
    return std::get<T>(replies[0]);
  }
};

TEST(Gx1Emulator, AnswersTheCommandsTheDriverUses) {
  Gx1Emulator emu(fixed_attitude());
  ASSERT_EQ(emu.start(), 0);
  Host host(emu.device_path());
  EXPECT_EQ(host.ask<FirmwareReply>(encode_poll(cmd::firmware)).number, 3102);
  EXPECT_EQ(host.ask<SerialNumberReply>(encode_poll(cmd::serial_number)).number, 1234);
  EXPECT_EQ(host.ask<EepromReply>(encode_eeprom_read(kEepromGyroGainScale)).value, 8500);
  EXPECT_EQ(host.ask<EepromReply>(encode_eeprom_read(kEepromAccelGainScale)).value, 7000);
  EXPECT_EQ(host.ask<TemperatureReply>(encode_poll(cmd::temperature)).raw, 0x2666);

  const EulerReply e = host.ask<EulerReply>(encode_poll(cmd::stab_euler));
  EXPECT_EQ(e.header, cmd::stab_euler);
  EXPECT_EQ(e.roll, counts_from_degrees(kFixed.roll_deg));
  EXPECT_EQ(e.pitch, counts_from_degrees(kFixed.pitch_deg));
  EXPECT_EQ(e.yaw, counts_from_degrees(kFixed.yaw_deg));

  const EulerVectorsReply v = host.ask<EulerVectorsReply>(encode_poll(cmd::stab_euler_vectors));
  EXPECT_EQ(v.roll, e.roll);
  EXPECT_EQ(v.accel[2], -4681);                               // -1 G at the default accel gain (V3)
  EXPECT_EQ(v.rate, (std::array<std::int16_t, 3>{0, 0, 0}));  // a fixed attitude does not turn

  // The quaternion is the same attitude: back to 3-2-1 Euler angles, within the
  // 1/8192 quantisation of its terms.
  const QuaternionReply qr = host.ask<QuaternionReply>(encode_poll(cmd::stab_quaternion));
  const double w = quaternion_from_counts(qr.q[0]), x = quaternion_from_counts(qr.q[1]),
               y = quaternion_from_counts(qr.q[2]), z = quaternion_from_counts(qr.q[3]);
  const double deg = 180.0 / std::numbers::pi;
  EXPECT_NEAR(w * w + x * x + y * y + z * z, 1.0, 1e-3);
  EXPECT_NEAR(std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)) * deg, kFixed.roll_deg, 0.05);
  EXPECT_NEAR(std::asin(2 * (w * y - z * x)) * deg, kFixed.pitch_deg, 0.05);
  EXPECT_NEAR(std::remainder(std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)) * deg - kFixed.yaw_deg, 360.0),
              0.0, 0.05);

  const EmulatorCounters c = emu.counters();
  EXPECT_EQ(c.replies, 8u);
  EXPECT_EQ(c.packets, 0u);  // nothing streamed unasked
}

TEST(Gx1Emulator, StreamsAtItsOwnPaceUntilStopped) {
  EmulatorOptions o = fixed_attitude();
  o.rate_hz = 200.0;
  o.record_limit = 1000;
  Gx1Emulator emu(o);
  ASSERT_EQ(emu.start(), 0);
  Host host(emu.device_path());
  host.send(encode_continuous_start(cmd::stab_euler));
  const auto streamed = host.collect(500);
  ASSERT_GE(streamed.size(), 2u);
  ASSERT_TRUE(std::holds_alternative<ContinuousAck>(streamed[0]));
  EXPECT_EQ(std::get<ContinuousAck>(streamed[0]).streamed(), cmd::stab_euler);
  // Paced by the emulator: about 100 packets in 0.5 s, not thousands (a pty would take them).
  EXPECT_GT(streamed.size(), 50u);
  EXPECT_LT(streamed.size(), 130u);
  for (std::size_t i = 1; i < streamed.size(); ++i) ASSERT_TRUE(std::holds_alternative<EulerReply>(streamed[i]));

  host.send(encode_continuous_stop());
  const auto after_stop = host.collect(200);
  ASSERT_FALSE(after_stop.empty());
  // Possibly a packet already on its way, then the stop's ack, then silence.
  ASSERT_TRUE(std::holds_alternative<ContinuousAck>(after_stop.back()));
  EXPECT_EQ(std::get<ContinuousAck>(after_stop.back()).streamed(), 0);
  EXPECT_LE(after_stop.size(), 2u);
  EXPECT_TRUE(host.collect(100).empty());
  EXPECT_EQ(emu.counters().stops, 1u);
  EXPECT_EQ(emu.counters().starts, 1u);
}

TEST(Gx1Emulator, CanStartWithAStreamLeftRunning) {
  EmulatorOptions o = fixed_attitude();
  o.left_streaming = cmd::stab_euler;
  Gx1Emulator emu(o);
  ASSERT_EQ(emu.start(), 0);
  Host host(emu.device_path());
  host.parser.confirm_resync(false);
  const auto replies = host.collect(200);
  EXPECT_GT(replies.size(), 5u);  // unasked
  EXPECT_EQ(emu.counters().starts, 0u);
}

TEST(Gx1Emulator, HangsUpAndReappearsBehindItsLink) {
  const std::string link = testing::TempDir() + "/gx1-emulator-test-link";
  ::unlink(link.c_str());
  EmulatorOptions o = fixed_attitude();
  o.link = link;
  Gx1Emulator emu(o);
  ASSERT_EQ(emu.start(), 0);
  char target[128] = {};
  ASSERT_GT(readlink(link.c_str(), target, sizeof target - 1), 0);
  EXPECT_EQ(std::string(target), emu.slave_path());

  SerialPort port(link);
  ASSERT_EQ(port.open(), 0);
  emu.hang_up(1000);
  std::uint8_t buf[16];
  ReadResult r;
  for (int i = 0; i < 20 && r.status != ReadStatus::hangup; ++i) r = port.read_some(buf, 50);
  EXPECT_EQ(r.status, ReadStatus::hangup);
  struct stat st {};
  EXPECT_NE(lstat(link.c_str(), &st), 0) << "the link stays while the device is gone";
  port.close();

  int rc = -1;
  for (int i = 0; i < 150 && rc != 0; ++i) {
    sleep_until(monotonic_ns() + 20'000'000);
    rc = port.open();
  }
  ASSERT_EQ(rc, 0) << "the device came back behind the same path";
  port.close();
  Host again(link);
  EXPECT_EQ(again.ask<FirmwareReply>(encode_poll(cmd::firmware)).number, 3102);
  EXPECT_EQ(emu.counters().hangups, 1u);
  emu.stop();
  EXPECT_NE(lstat(link.c_str(), &st), 0) << "stop() removes the link";
}

TEST(Gx1Emulator, RefusesToReplaceAFileWithItsLink) {
  const std::string path = testing::TempDir() + "/gx1-emulator-test-file";
  std::ofstream(path) << "precious";
  EmulatorOptions o;
  o.link = path;
  Gx1Emulator emu(o);
  EXPECT_EQ(emu.start(), -EEXIST);
  std::string content;
  std::ifstream(path) >> content;
  EXPECT_EQ(content, "precious");
  ::unlink(path.c_str());
}

// `gx1-emulate --link X` once deleted a user's X.new on the way to re-pointing X.
TEST(Gx1Emulator, AUsersFileBesideTheLinkIsLeftAlone) {
  const std::string link = testing::TempDir() + "/gx1-emulator-test-beside";
  ::unlink(link.c_str());
  std::ofstream(link + ".new") << "precious";
  EmulatorOptions o;
  o.link = link;
  Gx1Emulator emu(o);
  ASSERT_EQ(emu.start(), 0);
  char target[256] = {};
  EXPECT_GT(readlink(link.c_str(), target, sizeof target - 1), 0);
  emu.stop();
  std::string content;
  std::ifstream(link + ".new") >> content;
  EXPECT_EQ(content, "precious");
  ::unlink((link + ".new").c_str());
}

TEST(Gx1Emulator, FlipsBitsAndInjectsGarbageAsScheduled) {
  EmulatorOptions o;
  o.rate_hz = 200.0;
  o.tick_seconds = 0.001;  // unique ticks per packet, to tell packets apart
  o.record_limit = 1000;
  // Faults three packets apart: the parser's resync confirmation costs a packet only
  // when two faults touch it from both sides (see gx1_protocol.hpp).
  o.faults.flip_every = 6;
  o.faults.flip_phase = 3;
  o.faults.garbage_every = 6;
  o.faults.garbage_phase = 0;
  Gx1Emulator emu(o);
  ASSERT_EQ(emu.start(), 0);
  Host host(emu.device_path());
  host.send(encode_continuous_start(cmd::stab_euler));
  const auto replies = host.collect(400);
  const auto sent = emu.sent();
  ASSERT_GT(sent.size(), 40u);
  for (const SentPacket& p : sent) EXPECT_EQ(p.intact, p.number % 6 != 3) << p.number;
  const EmulatorCounters c = emu.counters();
  EXPECT_EQ(c.flipped, (c.packets + 3) / 6);
  EXPECT_EQ(c.garbage_bytes, 7 * (c.packets / 6));
  EXPECT_GT(host.parser.counters().bad_checksums, 0u);

  std::vector<test::ReceivedEuler> received;
  for (const Reply& r : replies)
    if (!std::holds_alternative<ContinuousAck>(r)) received.push_back(test::euler_of(r));
  EXPECT_GT(test::expect_exactly_the_intact_packets(received, sent), 30u);
}

}  // namespace
}  // namespace ccdlane::gx1
