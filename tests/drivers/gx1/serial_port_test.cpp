// The termios transport over real pty pairs: line settings read back from the kernel,
// binary transparency, bounded reads, hang-up, reopen with backoff, adopted fds.
#include "drivers/gx1/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/device_state.hpp"

namespace ccdlane::gx1 {
namespace {

// A pty pair left in the kernel's default (cooked, echoing) state, as a fresh
// /dev/ttyUSB0 would be: the port must set everything itself.
struct Pty {
  UniqueFd master;
  std::string slave_path;
  Pty() {
    int m = -1, s = -1;
    char name[128];
    if (openpty(&m, &s, name, nullptr, nullptr) != 0) throw std::runtime_error("openpty");
    master.reset(m);
    ::close(s);
    slave_path = name;
  }
  std::vector<std::uint8_t> read_master(std::size_t n, int timeout_ms = 1000) const {
    std::vector<std::uint8_t> out;
    const std::int64_t deadline = monotonic_ns() + std::int64_t{timeout_ms} * 1'000'000;
    while (out.size() < n && monotonic_ns() < deadline) {
      pollfd p{master.get(), POLLIN, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      std::uint8_t buf[256];
      const ssize_t r = ::read(master.get(), buf, std::min(sizeof buf, n - out.size()));
      if (r > 0) out.insert(out.end(), buf, buf + r);
    }
    return out;
  }
};

struct LogLines {
  std::vector<std::string> lines;
  LogSink sink() {
    return [this](LogLevel, const char*, const char* l) { lines.emplace_back(l); };
  }
  int count(const std::string& needle) const {
    int n = 0;
    for (const auto& l : lines) n += l.find(needle) != std::string::npos;
    return n;
  }
};

std::vector<std::uint8_t> read_port(SerialPort& port, std::size_t n) {
  std::vector<std::uint8_t> out;
  std::uint8_t buf[512];
  for (int i = 0; i < 100 && out.size() < n; ++i) {
    const ReadResult r = port.read_some(buf, 50);
    if (r.status == ReadStatus::data) out.insert(out.end(), buf, buf + r.bytes);
    if (r.status == ReadStatus::hangup || r.status == ReadStatus::error) break;
  }
  return out;
}

TEST(SerialPort, SetsRaw38400NoFlowControlAndTheKernelAgrees) {
  Pty pty;
  SerialPort port(pty.slave_path);
  ASSERT_EQ(port.open(), 0);
  termios t{};
  UniqueFd other(::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY));  // the kernel's view, not ours
  ASSERT_TRUE(other);
  ASSERT_EQ(tcgetattr(other.get(), &t), 0);
  EXPECT_EQ(cfgetispeed(&t), B38400);
  EXPECT_EQ(cfgetospeed(&t), B38400);
  EXPECT_EQ(t.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
  EXPECT_FALSE(t.c_cflag & (PARENB | CSTOPB | CRTSCTS));
  EXPECT_TRUE(t.c_cflag & CLOCAL);
  EXPECT_TRUE(t.c_cflag & CREAD);
  EXPECT_FALSE(t.c_iflag & (IXON | IXOFF | IXANY | ICRNL | INLCR | IGNCR | ISTRIP | BRKINT | PARMRK));
  EXPECT_FALSE(t.c_oflag & OPOST);
  EXPECT_FALSE(t.c_lflag & (ECHO | ICANON | ISIG | IEXTEN));
  const int flags = fcntl(port.fd(), F_GETFL);
  EXPECT_TRUE(flags & O_NONBLOCK);
  EXPECT_TRUE(fcntl(port.fd(), F_GETFD) & FD_CLOEXEC);
}

TEST(SerialPort, EveryByteValuePassesUnchangedBothWays) {
  Pty pty;
  SerialPort port(pty.slave_path);
  ASSERT_EQ(port.open(), 0);
  std::vector<std::uint8_t> all(256);
  for (int i = 0; i < 256; ++i) all[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  // Sensor to host: 0x0D, 0x11, 0x13, 0x03 (VINTR)... must not be translated or eaten.
  ASSERT_EQ(::write(pty.master.get(), all.data(), all.size()), 256);
  EXPECT_EQ(read_port(port, 256), all);
  // Host to sensor: no output processing (0x0A would become 0D 0A with OPOST).
  ASSERT_EQ(port.write_all(all, 1000), 0);
  EXPECT_EQ(pty.read_master(256), all);
  EXPECT_EQ(port.counters().bytes_read, 256u);
  EXPECT_EQ(port.counters().bytes_written, 256u);
}

TEST(SerialPort, ReadTimesOutWhenTheLineIsQuiet) {
  Pty pty;
  SerialPort port(pty.slave_path);
  ASSERT_EQ(port.open(), 0);
  std::uint8_t buf[16];
  const std::int64_t t0 = monotonic_ns();
  const ReadResult r = port.read_some(buf, 30);
  EXPECT_EQ(r.status, ReadStatus::timeout);
  EXPECT_GE(r.t_ns - t0, 29'000'000);  // it did wait (poll), and returned
}

TEST(SerialPort, MasterClosingIsAHangUp) {
  Pty pty;
  SerialPort port(pty.slave_path);
  ASSERT_EQ(port.open(), 0);
  const std::uint8_t last[3] = {1, 2, 3};
  ASSERT_EQ(::write(pty.master.get(), last, 3), 3);
  pty.master.reset();
  std::uint8_t buf[16];
  ReadResult r = port.read_some(buf, 100);
  if (r.status == ReadStatus::data) r = port.read_some(buf, 100);  // bytes queued before the hang-up
  EXPECT_EQ(r.status, ReadStatus::hangup);
  EXPECT_EQ(port.counters().hangups, 1u);
  EXPECT_TRUE(SerialPort::is_hangup_error(-port.write_all(last, 100)));
}

TEST(SerialPort, ReopensWithDoublingBackoffOnceTheDeviceIsBack) {
  const std::string path = testing::TempDir() + "/gx1-serial-port-test-link";
  ::unlink(path.c_str());
  LogLines log;
  SerialPort port(path, log.sink(), BackoffOptions{10, 40});
  std::int64_t now = 1'000'000'000;
  EXPECT_EQ(port.reopen_with_backoff(now), -ENOENT);
  EXPECT_EQ(port.next_attempt_ns(), now + 10'000'000);
  EXPECT_EQ(port.reopen_with_backoff(now + 5'000'000), -EAGAIN);  // not yet due
  now += 10'000'000;
  EXPECT_EQ(port.reopen_with_backoff(now), -ENOENT);
  EXPECT_EQ(port.next_attempt_ns(), now + 20'000'000);
  now += 20'000'000;
  EXPECT_EQ(port.reopen_with_backoff(now), -ENOENT);
  EXPECT_EQ(port.next_attempt_ns(), now + 40'000'000);
  now += 40'000'000;
  EXPECT_EQ(port.reopen_with_backoff(now), -ENOENT);
  EXPECT_EQ(port.next_attempt_ns(), now + 40'000'000);  // capped
  EXPECT_EQ(port.counters().open_failures, 4u);

  Pty pty;  // the device appears behind the path
  ASSERT_EQ(::symlink(pty.slave_path.c_str(), path.c_str()), 0);
  now += 40'000'000;
  EXPECT_EQ(port.reopen_with_backoff(now), 0);
  EXPECT_TRUE(port.is_open());
  port.reset_backoff();
  port.back_off(now);  // opened, but the device did not answer: closed, first delay again
  EXPECT_FALSE(port.is_open());
  EXPECT_EQ(port.next_attempt_ns(), now + 10'000'000);
  ::unlink(path.c_str());
}

TEST(SerialPort, ASecondCcdlaneProcessGetsBusy) {
  Pty pty;
  SerialPort first(pty.slave_path), second(pty.slave_path);
  ASSERT_EQ(first.open(), 0);
  EXPECT_EQ(second.open(), -EBUSY);
  first.close();
  EXPECT_EQ(second.open(), 0);
}

TEST(SerialPort, MissingModemLinesAreReportedOnceAndIgnored) {
  Pty pty;
  LogLines log;
  SerialPort port(pty.slave_path, log.sink());
  ASSERT_EQ(port.open(), 0);
  ASSERT_EQ(port.open(), 0);
  EXPECT_EQ(log.count("modem lines not supported"), 1);
  EXPECT_EQ(log.count(pty.slave_path), 1);  // the device is named on the line
}

TEST(SerialPort, AdoptsAnOpenPty) {
  Pty pty;
  SerialPort port("");
  UniqueFd fd(::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY));  // blocking, as a caller may hand it
  ASSERT_EQ(port.adopt(std::move(fd)), 0);
  EXPECT_TRUE(fcntl(port.fd(), F_GETFL) & O_NONBLOCK);
  const std::uint8_t ping[2] = {0x11, 0x13};
  ASSERT_EQ(::write(pty.master.get(), ping, 2), 2);
  EXPECT_EQ(read_port(port, 2), (std::vector<std::uint8_t>{0x11, 0x13}));
  EXPECT_EQ(port.reopen_with_backoff(monotonic_ns()), 0);  // still open: nothing to do
  port.close();
  EXPECT_EQ(port.open(), -ENODEV);  // no path to reopen by
}

// `[gyro] device = "some.toml"` once had its first bytes overwritten by the handshake: a
// regular file, a FIFO or a directory by path is refused before anything is written.
TEST(SerialPort, OnlyACharacterDeviceIsOpenedByPath) {
  const std::string dir = testing::TempDir() + "/serial-" + std::to_string(getpid());
  ::mkdir(dir.c_str(), 0700);
  const std::string file = dir + "/some.toml", fifo = dir + "/fifo";
  {
    std::FILE* f = std::fopen(file.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("[camera]\n", f);
    std::fclose(f);
  }
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {file, fifo}) {
    SerialPort port(path);
    EXPECT_EQ(port.open(), SerialPort::kNotACharacterDevice) << path;
    EXPECT_FALSE(port.is_open());
  }
  EXPECT_EQ(SerialPort(dir).open(), -EISDIR);
  char text[32] = "";
  std::FILE* f = std::fopen(file.c_str(), "r");
  ASSERT_NE(f, nullptr);
  ASSERT_NE(std::fgets(text, sizeof text, f), nullptr);
  std::fclose(f);
  EXPECT_STREQ(text, "[camera]\n") << "not a byte written";
  EXPECT_STREQ(serial_open_error(SerialPort::kNotACharacterDevice),
               "not a character device (a serial port or a pty): refused");
  Pty pty;
  SerialPort port(pty.slave_path);
  EXPECT_EQ(port.open(), 0) << "a pty is a character device";
  ::unlink(file.c_str());
  ::unlink(fifo.c_str());
  ::rmdir(dir.c_str());
}

TEST(SerialPort, AdoptsAPipeAsAPlainByteStream) {
  int p[2];
  ASSERT_EQ(pipe(p), 0);
  UniqueFd write_end(p[1]);
  LogLines log;
  SerialPort port("pipe", log.sink());
  ASSERT_EQ(port.adopt(UniqueFd(p[0])), 0);
  EXPECT_EQ(log.count("not a terminal"), 1);
  EXPECT_EQ(port.flush(), 0);
  ASSERT_EQ(::write(write_end.get(), "\x0e\x01", 2), 2);
  EXPECT_EQ(read_port(port, 2), (std::vector<std::uint8_t>{0x0E, 0x01}));
  write_end.reset();
  std::uint8_t buf[4];
  EXPECT_EQ(port.read_some(buf, 100).status, ReadStatus::hangup);  // end of the stream
}

}  // namespace
}  // namespace ccdlane::gx1
