// A test-owned systemd notification socket: what sd_notify sends to $NOTIFY_SOCKET
// arrives here, one datagram per message.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace ccdlane::test {

class NotifySocket {
 public:
  // Binds an AF_UNIX datagram socket at `path`.
  explicit NotifySocket(std::string path);
  ~NotifySocket();
  NotifySocket(const NotifySocket&) = delete;
  NotifySocket& operator=(const NotifySocket&) = delete;

  const std::string& path() const { return path_; }
  // The next datagram, or nullopt after timeout_ms.
  std::optional<std::string> receive(int timeout_ms);
  // Everything that arrives until `line` does (included) or timeout_ms passes.
  std::vector<std::string> receive_until(const std::string& line, int timeout_ms);
  // Everything already queued (waits at most timeout_ms for the first).
  std::vector<std::string> drain(int timeout_ms = 0);

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace ccdlane::test
