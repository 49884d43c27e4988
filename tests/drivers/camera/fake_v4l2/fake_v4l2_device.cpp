// The FUSE-served fake V4L2 camera. The file's bytes are the mmap buffers laid end to end;
// after writing a frame the producer invalidates that range of the page cache, so the
// client's next access to its shared mapping reads the new frame through read().
#define FUSE_USE_VERSION 35
#include "tests/drivers/camera/fake_v4l2/fake_v4l2_device.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <fuse3/fuse_lowlevel.h>

namespace ccdlane::test {
namespace {

constexpr std::size_t kPage = 4096;
constexpr off_t kFileSize = off_t{256} << 20;  // room for any buffer set; reads past data give zeros

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

int bytes_per_pixel(std::uint32_t fourcc) { return fourcc == V4L2_PIX_FMT_GREY ? 1 : 2; }

struct Control {
  const char* name;
  std::uint32_t type;
  std::int32_t min, max, step, def;
};
const std::map<std::uint32_t, Control> kControls = {
    {V4L2_CID_GAIN, {"Gain", V4L2_CTRL_TYPE_INTEGER, 0, 100, 1, 10}},
    {V4L2_CID_EXPOSURE_AUTO, {"Auto Exposure", V4L2_CTRL_TYPE_MENU, 0, 3, 1, V4L2_EXPOSURE_APERTURE_PRIORITY}},
    {V4L2_CID_EXPOSURE_ABSOLUTE, {"Exposure Time, Absolute", V4L2_CTRL_TYPE_INTEGER, 1, 10000, 1, 100}},
};

// A FUSE server that lives in the test process cannot answer the FLUSH the kernel sends
// when that process dies holding the node open: its exit would hang for ever. A small
// forked guardian watches the process and, if it dies (its main thread turns zombie)
// without saying goodbye, aborts just this mount's connection through fusectl.
// Only async-signal-safe calls after fork().
void guard(pid_t parent, int quit_fd, unsigned connection) {
  char stat_path[64] = "/proc/";
  char abort_path[96] = "/sys/fs/fuse/connections/";
  auto append_number = [](char* s, unsigned long v) {
    char digits[24];
    int n = 0;
    do digits[n++] = static_cast<char>('0' + v % 10);
    while ((v /= 10) != 0);
    while (*s) ++s;
    while (n) *s++ = digits[--n];
    *s = 0;
  };
  auto append = [](char* s, const char* t) {
    while (*s) ++s;
    while ((*s++ = *t++) != 0) {
    }
  };
  append_number(stat_path, static_cast<unsigned long>(parent));
  append(stat_path, "/stat");
  append_number(abort_path, connection);
  append(abort_path, "/abort");
  for (;;) {
    pollfd p{quit_fd, POLLIN, 0};
    if (poll(&p, 1, 100) > 0) _exit(0);  // goodbye (or the parent closed it cleanly)
    char buf[256];
    const int fd = open(stat_path, O_RDONLY);
    ssize_t n = fd >= 0 ? read(fd, buf, sizeof buf - 1) : -1;
    if (fd >= 0) close(fd);
    bool dead = n <= 0;
    if (n > 0) {
      buf[n] = 0;
      const char* c = buf;
      while (*c && *c != ')') ++c;
      dead = c[0] == ')' && c[1] == ' ' && (c[2] == 'Z' || c[2] == 'X');
    }
    if (dead) {
      const int a = open(abort_path, O_WRONLY);
      if (a >= 0) {
        (void)!write(a, "1", 1);
        close(a);
      }
      _exit(0);
    }
  }
}

struct Done {
  std::uint32_t index, sequence;
  std::int64_t t_ns;
};

}  // namespace

struct FakeV4l2Device::Impl {
  std::string path;
  FakeV4l2Options options;

  mutable std::mutex mutex;
  // Device state (guarded by mutex); reset on replug.
  bool unplugged = false;
  v4l2_pix_format pix{};
  double fps = 30;
  std::map<std::uint32_t, std::int32_t> control_values;
  std::vector<std::uint8_t> data;  // the buffers, each buffer_len bytes
  std::size_t buffer_len = 0;
  int buffer_count = 0;
  std::vector<bool> owned_by_device;  // queued or done
  std::deque<std::uint32_t> queued;
  std::deque<Done> done;
  bool streaming = false;
  bool stalled = false;
  int skip = 0;
  std::uint32_t sequence = 0;
  int streamons = 0;
  int opens = 0;
  fuse_pollhandle* poll_handle = nullptr;

  // The FUSE session of the current mount.
  fuse_session* session = nullptr;
  int stop_fd = -1;
  std::thread loop;
  pid_t guardian = -1;
  int guardian_fd = -1;  // closing it tells the guardian all is well

  std::thread producer;
  std::atomic<bool> running{true};

  void reset_device() {
    unplugged = false;
    fps = options.fps;
    pix = v4l2_pix_format{};
    pix.pixelformat = options.formats.empty() ? V4L2_PIX_FMT_GREY : options.formats.front();
    fit_format(pix);
    control_values.clear();
    for (const auto& [id, c] : kControls) control_values[id] = c.def;
    data.clear();
    buffer_len = 0;
    buffer_count = 0;
    owned_by_device.clear();
    queued.clear();
    done.clear();
    streaming = stalled = false;
    skip = 0;
    sequence = 0;
    opens = 0;  // descriptors of a previous mount never reach this one
  }

  // What a driver does with S_FMT/TRY_FMT: adjust to something it supports.
  void fit_format(v4l2_pix_format& f) const {
    if (std::find(options.formats.begin(), options.formats.end(), f.pixelformat) == options.formats.end())
      f.pixelformat = options.formats.empty() ? V4L2_PIX_FMT_GREY : options.formats.front();
    const auto exact = std::find(options.sizes.begin(), options.sizes.end(),
                                 std::pair<int, int>(static_cast<int>(f.width), static_cast<int>(f.height)));
    const auto size = exact != options.sizes.end() ? *exact : options.sizes.front();
    f.width = static_cast<std::uint32_t>(size.first);
    f.height = static_cast<std::uint32_t>(size.second);
    f.field = V4L2_FIELD_NONE;
    f.bytesperline = f.width * static_cast<std::uint32_t>(bytes_per_pixel(f.pixelformat));
    f.sizeimage = f.bytesperline * f.height;
    f.colorspace = V4L2_COLORSPACE_RAW;
  }

  void fill(std::uint32_t index, std::uint32_t seq) {
    std::uint8_t* b = data.data() + index * buffer_len;
    if (!options.frames.empty()) {
      const std::vector<std::uint8_t>& frame = options.frames[seq % options.frames.size()];
      std::memcpy(b, frame.data(), std::min<std::size_t>(frame.size(), pix.sizeimage));
      return;
    }
    const int w = static_cast<int>(pix.width), h = static_cast<int>(pix.height);
    for (int y = 0; y < h; ++y) {
      std::uint8_t* row = b + y * static_cast<std::ptrdiff_t>(pix.bytesperline);
      for (int x = 0; x < w; ++x) {
        switch (pix.pixelformat) {
          case V4L2_PIX_FMT_GREY: row[x] = fake_pixel8(seq, x, y); break;
          case V4L2_PIX_FMT_YUYV:
            row[2 * x] = fake_pixel8(seq, x, y);
            row[2 * x + 1] = static_cast<std::uint8_t>(x & 1 ? 200 : 50);  // V / U
            break;
          default: {  // 16-bit little endian
            const std::uint16_t v = fake_pixel16(seq, x, y);
            row[2 * x] = static_cast<std::uint8_t>(v & 0xff);
            row[2 * x + 1] = static_cast<std::uint8_t>(v >> 8);
          }
        }
      }
    }
  }

  // Takes the pending poll handle to wake it outside the lock.
  fuse_pollhandle* take_poll_handle() { return std::exchange(poll_handle, nullptr); }
  static void wake(fuse_pollhandle* ph) {
    if (ph) {
      fuse_lowlevel_notify_poll(ph);
      fuse_pollhandle_destroy(ph);
    }
  }

  void produce() {
    std::int64_t next = now_ns();
    while (running) {
      double rate;
      {
        std::lock_guard lock(mutex);
        rate = fps;
      }
      next += static_cast<std::int64_t>(1e9 / rate);
      const std::int64_t wait = next - now_ns();
      if (wait > 0)
        std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
      else
        next = now_ns();  // fell behind (loaded machine): do not burst to catch up
      std::unique_lock lock(mutex);
      if (!streaming || stalled || unplugged || session == nullptr) continue;
      const std::uint32_t seq = sequence++;
      if (skip > 0 || queued.empty()) {  // no buffer for this frame: it is lost, as on real hardware
        skip = std::max(0, skip - 1);
        continue;
      }
      const std::uint32_t index = queued.front();
      queued.pop_front();
      fill(index, seq);
      const std::int64_t t = now_ns();
      fuse_session* se = session;
      const off_t offset = static_cast<off_t>(index * buffer_len);
      const auto length = static_cast<off_t>(buffer_len);
      lock.unlock();
      // The client's mapping must not keep the previous frame's pages.
      fuse_lowlevel_notify_inval_inode(se, FUSE_ROOT_ID, offset, length);
      lock.lock();
      if (!streaming) continue;  // STREAMOFF meanwhile: the buffer went back to the client
      done.push_back({index, seq, t});
      fuse_pollhandle* ph = take_poll_handle();
      lock.unlock();
      wake(ph);
    }
  }

  // ---- FUSE operations -------------------------------------------------------------
  static Impl& of(fuse_req_t req) { return *static_cast<Impl*>(fuse_req_userdata(req)); }

  static void op_getattr(fuse_req_t req, fuse_ino_t ino, fuse_file_info*) {
    struct stat st {};
    st.st_ino = ino;
    st.st_mode = S_IFREG | 0666;
    st.st_nlink = 1;
    st.st_size = kFileSize;
    fuse_reply_attr(req, &st, 0.0);
  }

  static void op_open(fuse_req_t req, fuse_ino_t, fuse_file_info* fi) {
    Impl& d = of(req);
    std::lock_guard lock(d.mutex);
    if (d.unplugged) {
      fuse_reply_err(req, ENODEV);
      return;
    }
    ++d.opens;
    fi->direct_io = 0;  // page cache, so that shared mmap works
    fi->keep_cache = 0;
    fuse_reply_open(req, fi);
  }

  static void op_release(fuse_req_t req, fuse_ino_t, fuse_file_info*) {
    Impl& d = of(req);
    {
      std::lock_guard lock(d.mutex);
      --d.opens;
      // Closing the node ends streaming and frees the buffers, as in the V4L2 core.
      d.streaming = false;
      d.queued.clear();
      d.done.clear();
      d.data.clear();
      d.buffer_count = 0;
      d.owned_by_device.clear();
    }
    fuse_reply_err(req, 0);
  }

  static void op_read(fuse_req_t req, fuse_ino_t, size_t size, off_t off, fuse_file_info*) {
    Impl& d = of(req);
    std::vector<char> out(size, 0);
    {
      std::lock_guard lock(d.mutex);
      const auto have = static_cast<off_t>(d.data.size());
      if (off < have)
        std::memcpy(out.data(), d.data.data() + off,
                    static_cast<std::size_t>(std::min<off_t>(have - off, static_cast<off_t>(size))));
    }
    const std::size_t n = off >= kFileSize ? 0 : std::min<std::size_t>(size, static_cast<std::size_t>(kFileSize - off));
    fuse_reply_buf(req, out.data(), n);
  }

  static void op_poll(fuse_req_t req, fuse_ino_t, fuse_file_info*, fuse_pollhandle* ph) {
    Impl& d = of(req);
    unsigned revents = 0;
    fuse_pollhandle* old = nullptr;
    {
      std::lock_guard lock(d.mutex);
      if (d.unplugged)
        revents = POLLERR | POLLHUP;
      else if (!d.streaming)
        revents = POLLERR;
      else if (!d.done.empty())
        revents = POLLIN | POLLRDNORM;
      if (ph != nullptr) {
        if (revents == 0) {
          old = std::exchange(d.poll_handle, ph);
          ph = nullptr;
        }
      }
    }
    if (old) fuse_pollhandle_destroy(old);
    if (ph) fuse_pollhandle_destroy(ph);
    fuse_reply_poll(req, revents);
  }

  template <class T>
  static bool input(const void* in_buf, size_t in_bufsz, T& out) {
    if (in_bufsz < sizeof(T)) return false;
    std::memcpy(&out, in_buf, sizeof(T));
    return true;
  }

  static void op_ioctl(fuse_req_t req, fuse_ino_t, unsigned int cmd, void*, fuse_file_info*, unsigned flags,
                       const void* in_buf, size_t in_bufsz, size_t) {
    Impl& d = of(req);
    if (flags & FUSE_IOCTL_COMPAT) {
      fuse_reply_err(req, ENOSYS);
      return;
    }
    fuse_pollhandle* ph = nullptr;
    const int err = d.ioctl(req, cmd, in_buf, in_bufsz, ph);
    if (err) fuse_reply_err(req, err);
    wake(ph);
  }

  // Replies itself on success; returns an errno to reply with otherwise.
  int ioctl(fuse_req_t req, unsigned int cmd, const void* in, size_t in_size, fuse_pollhandle*& wake_ph) {
    std::lock_guard lock(mutex);
    if (unplugged) return ENODEV;
    switch (cmd) {
      case VIDIOC_QUERYCAP: {
        v4l2_capability c{};
        std::snprintf(reinterpret_cast<char*>(c.driver), sizeof c.driver, "ccdlane_fake");
        std::snprintf(reinterpret_cast<char*>(c.card), sizeof c.card, "%s", options.card.c_str());
        std::snprintf(reinterpret_cast<char*>(c.bus_info), sizeof c.bus_info, "fuse:%s", path.c_str());
        c.version = 0x060000;
        c.device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
        c.capabilities = c.device_caps | V4L2_CAP_DEVICE_CAPS;
        return reply(req, c);
      }
      case VIDIOC_ENUM_FMT: {
        v4l2_fmtdesc f{};
        if (!input(in, in_size, f)) return EINVAL;
        if (f.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || f.index >= options.formats.size()) return EINVAL;
        f.pixelformat = options.formats[f.index];
        std::snprintf(reinterpret_cast<char*>(f.description), sizeof f.description, "format %u", f.index);
        return reply(req, f);
      }
      case VIDIOC_G_FMT:
      case VIDIOC_S_FMT:
      case VIDIOC_TRY_FMT: {
        v4l2_format f{};
        if (!input(in, in_size, f) || f.type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return EINVAL;
        if (cmd == VIDIOC_G_FMT) {
          f.fmt.pix = pix;
        } else {
          fit_format(f.fmt.pix);
          if (cmd == VIDIOC_S_FMT) {
            if (buffer_count > 0) return EBUSY;
            pix = f.fmt.pix;
          }
        }
        return reply(req, f);
      }
      case VIDIOC_G_PARM:
      case VIDIOC_S_PARM: {
        v4l2_streamparm p{};
        if (!input(in, in_size, p) || p.type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return EINVAL;
        if (!options.frame_rate_control) return ENOTTY;
        auto& tpf = p.parm.capture.timeperframe;
        if (cmd == VIDIOC_S_PARM && tpf.numerator > 0 && tpf.denominator > 0)
          fps = std::clamp(double(tpf.denominator) / tpf.numerator, 1.0, options.max_fps);
        p.parm.capture = v4l2_captureparm{};
        p.parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
        tpf.numerator = 1000;
        tpf.denominator = static_cast<std::uint32_t>(std::lround(fps * 1000));
        return reply(req, p);
      }
      case VIDIOC_QUERYCTRL: {
        v4l2_queryctrl q{};
        if (!input(in, in_size, q) || !options.controls) return EINVAL;
        auto it = kControls.end();
        if (q.id & V4L2_CTRL_FLAG_NEXT_CTRL)
          it = kControls.upper_bound(q.id & ~(V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND));
        else
          it = kControls.find(q.id);
        if (it == kControls.end()) return EINVAL;
        q = v4l2_queryctrl{};
        q.id = it->first;
        q.type = it->second.type;
        std::snprintf(reinterpret_cast<char*>(q.name), sizeof q.name, "%s", it->second.name);
        q.minimum = it->second.min;
        q.maximum = it->second.max;
        q.step = it->second.step;
        q.default_value = it->second.def;
        return reply(req, q);
      }
      case VIDIOC_G_CTRL:
      case VIDIOC_S_CTRL: {
        v4l2_control c{};
        if (!input(in, in_size, c) || !options.controls) return EINVAL;
        const auto it = kControls.find(c.id);
        if (it == kControls.end()) return EINVAL;
        if (cmd == VIDIOC_S_CTRL) {
          if (c.value < it->second.min || c.value > it->second.max) return ERANGE;
          control_values[c.id] = c.value;
        }
        c.value = control_values[c.id];
        return reply(req, c);
      }
      case VIDIOC_REQBUFS: {
        v4l2_requestbuffers r{};
        if (!input(in, in_size, r) || r.type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return EINVAL;
        if (r.memory != V4L2_MEMORY_MMAP) return EINVAL;
        if (streaming) return EBUSY;
        buffer_count =
            static_cast<int>(std::min<std::uint32_t>(r.count, static_cast<std::uint32_t>(options.max_buffers)));
        buffer_len = (pix.sizeimage + kPage - 1) / kPage * kPage;
        data.assign(buffer_len * static_cast<std::size_t>(buffer_count), 0);
        owned_by_device.assign(static_cast<std::size_t>(buffer_count), false);
        queued.clear();
        done.clear();
        r.count = static_cast<std::uint32_t>(buffer_count);
        r.capabilities = V4L2_BUF_CAP_SUPPORTS_MMAP;
        return reply(req, r);
      }
      case VIDIOC_QUERYBUF:
      case VIDIOC_QBUF: {
        v4l2_buffer b{};
        if (!input(in, in_size, b) || b.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b.memory != V4L2_MEMORY_MMAP)
          return EINVAL;
        if (b.index >= static_cast<std::uint32_t>(buffer_count)) return EINVAL;
        if (cmd == VIDIOC_QBUF) {
          if (owned_by_device[b.index]) return EINVAL;
          owned_by_device[b.index] = true;
          queued.push_back(b.index);
        }
        b.length = static_cast<std::uint32_t>(buffer_len);
        b.m.offset = static_cast<std::uint32_t>(b.index * buffer_len);
        b.flags = V4L2_BUF_FLAG_MAPPED | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC |
                  (owned_by_device[b.index] ? V4L2_BUF_FLAG_QUEUED : 0);
        return reply(req, b);
      }
      case VIDIOC_DQBUF: {
        v4l2_buffer b{};
        if (!input(in, in_size, b) || b.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b.memory != V4L2_MEMORY_MMAP)
          return EINVAL;
        if (!streaming) return EINVAL;
        if (done.empty()) return EAGAIN;
        const Done f = done.front();
        done.pop_front();
        owned_by_device[f.index] = false;
        b.index = f.index;
        b.sequence = f.sequence;
        b.bytesused = pix.sizeimage;
        b.length = static_cast<std::uint32_t>(buffer_len);
        b.m.offset = static_cast<std::uint32_t>(f.index * buffer_len);
        b.field = V4L2_FIELD_NONE;
        b.flags = V4L2_BUF_FLAG_MAPPED | V4L2_BUF_FLAG_DONE | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        b.timestamp.tv_sec = f.t_ns / 1'000'000'000;
        b.timestamp.tv_usec = (f.t_ns % 1'000'000'000) / 1000;
        return reply(req, b);
      }
      case VIDIOC_STREAMON:
      case VIDIOC_STREAMOFF: {
        int type = 0;
        if (!input(in, in_size, type) || type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return EINVAL;
        if (cmd == VIDIOC_STREAMON) {
          if (buffer_count == 0) return EINVAL;
          if (!streaming) {
            streaming = true;
            stalled = false;
            sequence = 0;
            ++streamons;
          }
        } else {
          streaming = false;
          queued.clear();
          done.clear();
          std::fill(owned_by_device.begin(), owned_by_device.end(), false);
          wake_ph = take_poll_handle();
        }
        fuse_reply_ioctl(req, 0, nullptr, 0);
        return 0;
      }
      default: return ENOTTY;
    }
  }

  template <class T>
  static int reply(fuse_req_t req, const T& value) {
    fuse_reply_ioctl(req, 0, &value, sizeof value);
    return 0;
  }

  // ---- mounting ----------------------------------------------------------------------
  void mount() {
    {
      std::lock_guard lock(mutex);
      reset_device();
    }
    const int fd = ::open(path.c_str(), O_CREAT | O_WRONLY | O_CLOEXEC, 0666);  // the mount point
    if (fd < 0) throw std::runtime_error("fake v4l2: cannot create " + path + ": " + std::strerror(errno));
    ::close(fd);
    fuse_lowlevel_ops ops{};
    ops.getattr = op_getattr;
    ops.open = op_open;
    ops.release = op_release;
    ops.read = op_read;
    ops.poll = op_poll;
    ops.ioctl = op_ioctl;
    char arg0[] = "fake_v4l2";
    char* argv[] = {arg0, nullptr};
    fuse_args args = FUSE_ARGS_INIT(1, argv);
    fuse_session* se = fuse_session_new(&args, &ops, sizeof ops, this);
    if (se == nullptr) throw std::runtime_error("fake v4l2: fuse_session_new failed");
    if (fuse_session_mount(se, path.c_str()) != 0) {
      fuse_session_destroy(se);
      throw std::runtime_error("fake v4l2: cannot mount at " + path + " (needs CAP_SYS_ADMIN and /dev/fuse)");
    }
    stop_fd = eventfd(0, EFD_CLOEXEC);
    {
      std::lock_guard lock(mutex);
      session = se;
    }
    loop = std::thread([this, se] { serve(se); });
    // The kernel learns the file's size (the mmap range) only from a GETATTR.
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || st.st_size != kFileSize)
      throw std::runtime_error("fake v4l2: " + path + " does not show the served file");
    start_guardian(minor(st.st_dev));
  }

  void start_guardian(unsigned connection) {
    // fusectl in this (private) mount namespace; EBUSY: already there.
    ::mount("fusectl", "/sys/fs/fuse/connections", "fusectl", 0, nullptr);
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) return;
    const pid_t parent = getpid();
    const pid_t child = fork();
    if (child == 0) {
      close(fds[1]);
      guard(parent, fds[0], connection);
    }
    close(fds[0]);
    guardian = child;
    guardian_fd = fds[1];
  }

  void stop_guardian() {
    if (guardian_fd >= 0) ::close(std::exchange(guardian_fd, -1));
    if (guardian > 0) waitpid(std::exchange(guardian, -1), nullptr, 0);
  }

  void serve(fuse_session* se) {
    fuse_buf buf{};
    pollfd fds[2] = {{fuse_session_fd(se), POLLIN, 0}, {stop_fd, POLLIN, 0}};
    while (!fuse_session_exited(se)) {
      if (poll(fds, 2, -1) < 0) continue;
      if (fds[1].revents) break;
      if (!(fds[0].revents & POLLIN)) {
        if (fds[0].revents & (POLLERR | POLLHUP)) break;
        continue;
      }
      const int r = fuse_session_receive_buf(se, &buf);
      if (r == -EINTR || r == -EAGAIN) continue;
      if (r <= 0) break;
      fuse_session_process_buf(se, &buf);
    }
    std::free(buf.mem);
  }

  void unmount() {
    fuse_session* se;
    {
      std::lock_guard lock(mutex);
      se = std::exchange(session, nullptr);
    }
    if (se == nullptr) return;
    const std::uint64_t one = 1;
    (void)!write(stop_fd, &one, sizeof one);
    loop.join();
    ::close(stop_fd);
    stop_fd = -1;
    stop_guardian();
    fuse_session_unmount(se);  // closes the channel (open descriptors now fail) and detaches
    fuse_session_destroy(se);
    {
      std::lock_guard lock(mutex);
      if (poll_handle) fuse_pollhandle_destroy(std::exchange(poll_handle, nullptr));
    }
    ::unlink(path.c_str());  // the node is gone, as after a USB unplug
  }
};

FakeV4l2Device::FakeV4l2Device(std::string node_path, FakeV4l2Options options) : impl_(std::make_unique<Impl>()) {
  impl_->path = std::move(node_path);
  impl_->options = std::move(options);
  if (impl_->options.formats.empty()) impl_->options.formats = {V4L2_PIX_FMT_GREY};
  impl_->mount();
  impl_->producer = std::thread([this] { impl_->produce(); });
}

FakeV4l2Device::~FakeV4l2Device() {
  impl_->running = false;
  impl_->producer.join();
  impl_->unmount();
}

const std::string& FakeV4l2Device::path() const { return impl_->path; }

void FakeV4l2Device::unplug() {
  fuse_pollhandle* ph;
  {
    std::lock_guard lock(impl_->mutex);
    impl_->unplugged = true;
    ph = impl_->take_poll_handle();
  }
  Impl::wake(ph);
  // Give the client a moment to see ENODEV and close, as a driver would before the node
  // disappears; the unmount then happens whether or not it did.
  for (int i = 0; i < 100 && open_count() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  impl_->unmount();
}

void FakeV4l2Device::replug() { impl_->mount(); }

void FakeV4l2Device::stall_until_restart() {
  std::lock_guard lock(impl_->mutex);
  impl_->stalled = true;
}

void FakeV4l2Device::skip_frames(int n) {
  std::lock_guard lock(impl_->mutex);
  impl_->skip += n;
}

int FakeV4l2Device::streamon_count() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->streamons;
}

int FakeV4l2Device::open_count() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->opens;
}

std::int32_t FakeV4l2Device::control(std::uint32_t id) const {
  std::lock_guard lock(impl_->mutex);
  const auto it = impl_->control_values.find(id);
  return it == impl_->control_values.end() ? -1 : it->second;
}

double FakeV4l2Device::frame_rate() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->fps;
}

}  // namespace ccdlane::test
