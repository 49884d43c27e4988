// termios transport for the 3DM-GX1 (docs/gx1.md section 1): every line flag is set
// explicitly and read back, because tcsetattr() succeeds when any one change applied.
#include "drivers/gx1/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ccdlane::gx1 {
namespace {

// Input flags that would rewrite or swallow binary data (0x0D, 0x11, 0x13 occur all the time).
constexpr tcflag_t kForbiddenIflags =
    IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON | IXOFF | IXANY | INPCK | IUCLC | IMAXBEL;
constexpr tcflag_t kForbiddenLflags = ECHO | ECHOE | ECHOK | ECHONL | ICANON | ISIG | IEXTEN;
constexpr tcflag_t kForbiddenCflags = PARENB | CSTOPB | CRTSCTS;
constexpr tcflag_t kRequiredCflags = CS8 | CLOCAL | CREAD;

int remaining_ms(std::int64_t deadline_ns) {
  const std::int64_t left = deadline_ns - monotonic_ns();
  return left <= 0 ? 0 : static_cast<int>((left + 999'999) / 1'000'000);
}

}  // namespace

SerialPort::SerialPort(std::string path, LogSink log, BackoffOptions backoff)
    : path_(std::move(path)), log_(std::move(log)) {
  backoff_.configure(backoff.initial_ms, backoff.max_ms);
}

SerialPort::~SerialPort() { close(); }

const char* serial_open_error(int rc) {
  return rc == SerialPort::kNotACharacterDevice ? "not a character device (a serial port or a pty): refused"
                                                : std::strerror(-rc);
}

bool SerialPort::is_hangup_error(int error) {
  return error == EIO || error == ENXIO || error == ENODEV || error == EPIPE;
}

int SerialPort::open() {
  close();
  if (path_.empty()) return -ENODEV;
  UniqueFd fd(::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!fd) {
    const int e = errno;
    ++counters_.open_failures;
    return -e;
  }
  // A serial adapter and a pty are character devices; a file named by mistake (the
  // configuration itself) must not have its first bytes overwritten by the handshake.
  struct stat st {};
  if (fstat(fd.get(), &st) != 0 || !S_ISCHR(st.st_mode)) {
    ++counters_.open_failures;
    return kNotACharacterDevice;
  }
  // Two readers on one serial line steal each other's bytes (the daemon and a
  // `ccdlane gx1` run by hand): an advisory lock keeps ccdlane processes apart and,
  // unlike TIOCEXCL, is released by the kernel if the holder crashes.
  if (flock(fd.get(), LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
    ++counters_.open_failures;
    return -EBUSY;
  }
  fd_ = std::move(fd);
  if (const int rc = configure(); rc < 0) {
    fd_.reset();
    ++counters_.open_failures;
    return rc;
  }
  ++counters_.opens;
  return 0;
}

int SerialPort::adopt(UniqueFd fd) {
  close();
  if (!fd) return -EBADF;
  fd_ = std::move(fd);
  // The descriptor may have come without O_NONBLOCK; reads must never block.
  const int flags = fcntl(fd_.get(), F_GETFL);
  if (flags < 0 || fcntl(fd_.get(), F_SETFL, flags | O_NONBLOCK) < 0) {
    const int e = errno;
    fd_.reset();
    return -e;
  }
  if (const int rc = configure(); rc < 0) {
    fd_.reset();
    return rc;
  }
  ++counters_.opens;
  return 0;
}

void SerialPort::close() { fd_.reset(); }

int SerialPort::configure() {
  termios t{};
  if (tcgetattr(fd_.get(), &t) != 0) {
    const int e = errno;
    if (e != ENOTTY && e != EINVAL) return -e;
    is_tty_ = false;
    if (!not_a_tty_reported_) {
      log_to(log_, LogLevel::notice, "gyro", "serial %s: not a terminal: used as a plain byte stream", path_.c_str());
      not_a_tty_reported_ = true;
    }
    return 0;
  }
  is_tty_ = true;
  cfmakeraw(&t);
  t.c_iflag &= ~kForbiddenIflags;
  t.c_oflag &= ~static_cast<tcflag_t>(OPOST);
  t.c_lflag &= ~kForbiddenLflags;
  t.c_cflag &= ~(kForbiddenCflags | CSIZE);
  t.c_cflag |= kRequiredCflags;
  // VMIN=1 with O_NONBLOCK: an empty line gives EAGAIN, so read() == 0 can only mean
  // hang-up (with VMIN=0 it would also mean "no data").
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, B38400) != 0 || cfsetospeed(&t, B38400) != 0) return -errno;
  if (tcsetattr(fd_.get(), TCSANOW, &t) != 0) return -errno;
  if (const int rc = verify_termios(); rc < 0) return rc;

  // Some RS-232 level shifters are powered from DTR/RTS; the protocol itself ignores
  // them. A pty has no modem lines (ENOTTY): say so once and carry on.
  int lines = TIOCM_DTR | TIOCM_RTS;
  if (const int rc = ioctl(TIOCMBIS, &lines); rc < 0 && !modem_lines_reported_) {
    log_to(log_, LogLevel::notice, "gyro", "serial %s: modem lines not supported (%s): carrying on", path_.c_str(),
           std::strerror(-rc));
    modem_lines_reported_ = true;
  }
  return flush();
}

int SerialPort::verify_termios() {
  termios t{};
  if (tcgetattr(fd_.get(), &t) != 0) return -errno;
  const char* wrong = nullptr;
  if (t.c_iflag & kForbiddenIflags)
    wrong = "input processing (c_iflag) still on";
  else if (t.c_oflag & OPOST)
    wrong = "output processing (OPOST) still on";
  else if (t.c_lflag & kForbiddenLflags)
    wrong = "echo/canonical/signals (c_lflag) still on";
  else if ((t.c_cflag & CSIZE) != CS8)
    wrong = "character size is not 8 bits";
  else if (t.c_cflag & kForbiddenCflags)
    wrong = "parity, 2 stop bits or RTS/CTS still on";
  else if ((t.c_cflag & (CLOCAL | CREAD)) != (CLOCAL | CREAD))
    wrong = "CLOCAL/CREAD not set";
  else if (cfgetispeed(&t) != B38400 || cfgetospeed(&t) != B38400)
    wrong = "speed is not 38400";
  else if (t.c_cc[VMIN] != 1 || t.c_cc[VTIME] != 0)
    wrong = "VMIN/VTIME not 1/0";
  if (!wrong) return 0;
  log_to(log_, LogLevel::warning, "gyro", "serial %s: line settings did not read back: %s", path_.c_str(), wrong);
  return -EIO;
}

int SerialPort::ioctl(unsigned long request, void* arg) {
  const int rc = ::ioctl(fd_.get(), request, arg);
  return rc < 0 ? -errno : rc;
}

int SerialPort::flush() {
  if (!is_tty_) return 0;
  return tcflush(fd_.get(), TCIOFLUSH) == 0 ? 0 : -errno;
}

int SerialPort::drain_output() {
  if (!is_tty_) return 0;
  return tcdrain(fd_.get()) == 0 ? 0 : -errno;
}

ReadResult SerialPort::read_some(std::span<std::uint8_t> into, int timeout_ms) {
  ReadResult r;
  if (!fd_) {
    r.status = ReadStatus::error;
    r.error = EBADF;
    return r;
  }
  pollfd p{fd_.get(), POLLIN, 0};
  const int rc = ::poll(&p, 1, std::max(timeout_ms, 0));
  if (rc <= 0) {  // timeout, or a signal (EINTR): let the caller look at its stop flag
    r.t_ns = monotonic_ns();
    return r;
  }
  if (p.revents & POLLNVAL) {
    r.status = ReadStatus::error;
    r.error = EBADF;
    return r;
  }
  // POLLHUP may come with the last bytes still queued: read them first; the next call sees read() == 0.
  const ssize_t n = ::read(fd_.get(), into.data(), into.size());
  r.t_ns = monotonic_ns();
  if (n > 0) {
    r.status = ReadStatus::data;
    r.bytes = static_cast<std::size_t>(n);
    counters_.bytes_read += r.bytes;
    return r;
  }
  const int e = n == 0 ? 0 : errno;
  const bool would_block = n < 0 && (e == EAGAIN || e == EINTR);
  if (would_block && !(p.revents & (POLLHUP | POLLERR))) return r;  // spurious wake-up
  if (n == 0 || would_block || is_hangup_error(e)) {
    r.status = ReadStatus::hangup;
    r.error = is_hangup_error(e) ? e : EIO;
    ++counters_.hangups;
    return r;
  }
  r.status = ReadStatus::error;
  r.error = e;
  return r;
}

int SerialPort::write_all(std::span<const std::uint8_t> bytes, int timeout_ms) {
  if (!fd_) return -EBADF;
  const std::int64_t deadline = monotonic_ns() + std::int64_t{timeout_ms} * 1'000'000;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_.get(), bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      counters_.bytes_written += static_cast<std::uint64_t>(n);
      continue;
    }
    const int e = n < 0 ? errno : EAGAIN;
    if (e == EINTR) continue;
    if (e != EAGAIN) {
      if (is_hangup_error(e)) ++counters_.hangups;
      return -e;
    }
    const int left = remaining_ms(deadline);
    if (left == 0) return -ETIMEDOUT;
    pollfd p{fd_.get(), POLLOUT, 0};
    if (::poll(&p, 1, left) > 0 && (p.revents & (POLLHUP | POLLERR)) && !(p.revents & POLLOUT)) {
      ++counters_.hangups;
      return -EIO;
    }
  }
  return 0;
}

int SerialPort::reopen_with_backoff(std::int64_t now_ns) {
  if (is_open()) return 0;
  if (now_ns < next_attempt_ns()) return -EAGAIN;
  const int rc = open();
  if (rc < 0) back_off(now_ns);
  return rc;
}

void SerialPort::back_off(std::int64_t now_ns) {
  close();
  if (backing_off_) {
    backoff_.failed(now_ns);
  } else {
    backoff_.start(now_ns);
    backing_off_ = true;
  }
}

void SerialPort::reset_backoff() { backing_off_ = false; }

}  // namespace ccdlane::gx1
