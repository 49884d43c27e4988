// A fake V4L2 camera served by FUSE (low-level API) as a regular file: QUERYCAP, ENUM_FMT,
// G/S/TRY_FMT, G/S_PARM, controls, REQBUFS/QUERYBUF (mmap), QBUF/DQBUF, STREAMON/OFF and
// poll(), with a producer thread writing numbered frames. It lets tests drive the V4L2
// driver's real syscall path on machines without any video kernel driver.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ccdlane::test {

struct FakeV4l2Options {
  std::vector<std::uint32_t> formats;                  // offered fourccs, in ENUM_FMT order
  std::vector<std::pair<int, int>> sizes{{800, 600}};  // exact sizes it accepts; else the first
  double fps = 30.0;                                   // initial rate
  double max_fps = 240.0;
  bool frame_rate_control = true;  // V4L2_CAP_TIMEPERFRAME
  bool controls = true;            // exposure (auto, absolute) and gain
  int max_buffers = 16;
  std::string card = "ccdlane fake camera";
  // Pictures to serve instead of the numbered pattern, in turn, each exactly one frame of
  // the first offered format at the first size (e.g. rendered roads as YUYV).
  std::vector<std::vector<std::uint8_t>> frames{};
};

// The value of pixel (x, y) of frame `sequence`: 8-bit for GREY and the Y of YUYV,
// 16-bit for Y16. Tests check every pixel they receive against it.
constexpr std::uint8_t fake_pixel8(std::uint32_t sequence, int x, int y) {
  return static_cast<std::uint8_t>(sequence * 7u + static_cast<unsigned>(x) + 3u * static_cast<unsigned>(y));
}
constexpr std::uint16_t fake_pixel16(std::uint32_t sequence, int x, int y) {
  return static_cast<std::uint16_t>(sequence * 257u + 5u * static_cast<unsigned>(x) + 11u * static_cast<unsigned>(y));
}

class FakeV4l2Device {
 public:
  // Serves the device at `node_path` (a regular file is created there and mounted over).
  // Needs CAP_SYS_ADMIN; call from a private mount namespace. Throws std::runtime_error.
  FakeV4l2Device(std::string node_path, FakeV4l2Options options);
  ~FakeV4l2Device();
  FakeV4l2Device(const FakeV4l2Device&) = delete;
  FakeV4l2Device& operator=(const FakeV4l2Device&) = delete;

  const std::string& path() const;
  // The device vanishes: every call on an open descriptor fails with ENODEV and poll()
  // reports POLLERR|POLLHUP, then the node is unmounted (opening it fails).
  void unplug();
  // It comes back at the same path, fresh (as a re-enumerated USB camera does).
  void replug();
  // Stops producing frames until the next VIDIOC_STREAMON (a hung sensor).
  void stall_until_restart();
  // Produces the next `n` frames with no buffer to put them in (sequence still counts).
  void skip_frames(int n);

  int streamon_count() const;
  int open_count() const;
  std::int32_t control(std::uint32_t id) const;
  double frame_rate() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ccdlane::test
