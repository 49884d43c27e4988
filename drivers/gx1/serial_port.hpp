// The gyro's serial line over plain termios: owns the fd, sets raw 38400 8N1 with no flow
// control and reads it back, bounded poll() reads, write-all, hang-up detection, and
// reopening by path with backoff after the device went away (USB adapters come and go).
#pragma once

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "base/log.hpp"
#include "base/unique_fd.hpp"
#include "drivers/device_state.hpp"

namespace ccdlane::gx1 {

enum class ReadStatus : std::uint8_t {
  data,     // `bytes` > 0 bytes were read
  timeout,  // nothing within the timeout
  hangup,   // the device is gone (POLLHUP with nothing left, read() == 0, EIO): reopen
  error,    // another failure (`error` says which); the fd is probably unusable
};

struct ReadResult {
  ReadStatus status = ReadStatus::timeout;
  std::size_t bytes = 0;
  int error = 0;          // errno for hangup/error, else 0
  std::int64_t t_ns = 0;  // CLOCK_MONOTONIC right after the read returned
};

struct SerialCounters {
  std::uint64_t bytes_read = 0;
  std::uint64_t bytes_written = 0;
  std::uint64_t opens = 0;  // successful opens (the first one included) and adoptions
  std::uint64_t open_failures = 0;
  std::uint64_t hangups = 0;
};

struct BackoffOptions {
  int initial_ms = 100;
  int max_ms = 2000;
};

// The reason for open()'s result: kNotACharacterDevice says what it is, others strerror.
const char* serial_open_error(int rc);

class SerialPort {
 public:
  // Wire time of one byte at 38400 baud, 10 bits with start and stop bit.
  static constexpr std::int64_t kByteTimeNs = 1'000'000'000LL * 10 / 38400;

  // `path` may be empty for a port that is only ever adopt()ed (then it cannot reopen).
  explicit SerialPort(std::string path, LogSink log = {}, BackoffOptions backoff = {});
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Opens `path` (O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC) and configures it.
  // Returns 0 or -errno (-EBUSY: another ccdlane process holds it; -EIO: the line
  // settings did not read back as set; kNotACharacterDevice: `path` is a regular file, a
  // FIFO or a directory, refused before anything is configured or written).
  int open();
  static constexpr int kNotACharacterDevice = -ENOTTY;
  // Takes an already-open fd (a pty, a pipe) and configures it like open() would. A
  // descriptor that is not a terminal is used as a plain byte stream (logged once).
  int adopt(UniqueFd fd);
  void close();
  bool is_open() const { return fd_.valid(); }
  int fd() const { return fd_.get(); }
  const std::string& path() const { return path_; }

  // Waits up to timeout_ms (0: don't wait) and reads what is there into `into`.
  // Never blocks longer, never allocates.
  ReadResult read_some(std::span<std::uint8_t> into, int timeout_ms);

  // Writes every byte or fails: 0, -ETIMEDOUT when the line would not take them within
  // timeout_ms, -EIO/-ENXIO/-EPIPE when the device is gone, other -errno.
  int write_all(std::span<const std::uint8_t> bytes, int timeout_ms);

  // Discards received-but-unread and written-but-unsent bytes (tcflush TCIOFLUSH).
  int flush();
  // Waits until written bytes have left (tcdrain): a few ms at most with no flow control.
  int drain_output();

  // Recovery after the device went away. reopen_with_backoff() tries open() once the
  // current delay has passed (-EAGAIN before that) and lengthens the delay after a
  // failure; back_off() closes and lengthens it after a failure the caller saw (the port
  // opened but the device did not answer); reset_backoff() once the device works again.
  // Delays double from BackoffOptions::initial_ms up to max_ms.
  int reopen_with_backoff(std::int64_t now_ns);
  void back_off(std::int64_t now_ns);
  void reset_backoff();
  // When the next reopen attempt is due (CLOCK_MONOTONIC ns; 0: at once).
  std::int64_t next_attempt_ns() const { return backing_off_ ? backoff_.due_ns() : 0; }

  const SerialCounters& counters() const { return counters_; }

  // Whether a read/write error means the device has gone away (reopen) rather than a bug.
  static bool is_hangup_error(int error);

 private:
  int configure();
  int verify_termios();
  // The one place this file calls ioctl(): returns the result or -errno.
  int ioctl(unsigned long request, void* arg);

  std::string path_;
  LogSink log_;
  ReopenBackoff backoff_;
  bool backing_off_ = false;  // a failure since the last reset_backoff(): attempts wait
  UniqueFd fd_;
  bool is_tty_ = true;
  bool modem_lines_reported_ = false;
  bool not_a_tty_reported_ = false;
  SerialCounters counters_;
};

}  // namespace ccdlane::gx1
