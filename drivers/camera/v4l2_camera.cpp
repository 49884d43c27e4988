// The V4L2 camera: every call goes through V4l2Device::ioctl; nothing on the capture
// path (including recovery) allocates, so problems are written into fixed buffers.
#include "drivers/camera/v4l2_camera.hpp"

#include <linux/videodev2.h>
#include <poll.h>
#include <sys/mman.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace ccdlane {
namespace {

struct FormatChoice {
  std::uint32_t fourcc;
  WirePixels wire;
  int significant_bits;
};

// In order of preference for each output format.
constexpr FormatChoice kMono8Choices[] = {
    {V4L2_PIX_FMT_GREY, WirePixels::mono8, 8},
    {V4L2_PIX_FMT_YUYV, WirePixels::yuyv, 8},
    {V4L2_PIX_FMT_UYVY, WirePixels::uyvy, 8},
};
// Full-resolution colour first; the 2x2 demosaic of Bayer last.
constexpr FormatChoice kColourChoices[] = {
    {V4L2_PIX_FMT_RGB24, WirePixels::rgb24, 8},       {V4L2_PIX_FMT_BGR24, WirePixels::bgr24, 8},
    {V4L2_PIX_FMT_YUYV, WirePixels::yuyv, 8},         {V4L2_PIX_FMT_UYVY, WirePixels::uyvy, 8},
    {V4L2_PIX_FMT_SRGGB8, WirePixels::bayer_rggb, 8}, {V4L2_PIX_FMT_SBGGR8, WirePixels::bayer_bggr, 8},
    {V4L2_PIX_FMT_SGRBG8, WirePixels::bayer_grbg, 8}, {V4L2_PIX_FMT_SGBRG8, WirePixels::bayer_gbrg, 8},
};
constexpr FormatChoice kMono16Choices[] = {
    {V4L2_PIX_FMT_Y16, WirePixels::mono16_le, 16},
    {V4L2_PIX_FMT_Y16_BE, WirePixels::mono16_be, 16},
    {V4L2_PIX_FMT_Y12, WirePixels::mono16_le, 12},
    {V4L2_PIX_FMT_Y10, WirePixels::mono16_le, 10},
};

// The first choice the device offers among `choices`, or null.
template <std::size_t N>
const FormatChoice* first_offered(const FormatChoice (&choices)[N], const std::uint32_t* offered, int n_offered) {
  for (const FormatChoice& c : choices)
    for (int i = 0; i < n_offered; ++i)
      if (offered[i] == c.fourcc) return &c;
  return nullptr;
}

struct FourCc {
  char text[5];
};
FourCc fourcc_text(std::uint32_t f) {
  FourCc t{};
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((f >> (8 * i)) & 0xff);
    t.text[i] = std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  }
  return t;
}

const char* errno_name(int neg_errno) {
  const char* n = strerrorname_np(-neg_errno);
  return n ? n : "unknown error";
}

// The errors with which a node says its device is gone (USB unplug: ENODEV; a FUSE or
// otherwise disconnected node: ENOTCONN, ENXIO).
bool device_gone(int neg_errno) { return neg_errno == -ENODEV || neg_errno == -ENXIO || neg_errno == -ENOTCONN; }

// Control names compared on letters and digits only, ignoring case: "Exposure Time,
// Absolute" == "exposure_time_absolute".
bool same_control_name(const char* a, const char* b) {
  for (;;) {
    while (*a && !std::isalnum(static_cast<unsigned char>(*a))) ++a;
    while (*b && !std::isalnum(static_cast<unsigned char>(*b))) ++b;
    if (!*a || !*b) return !*a && !*b;
    if (std::tolower(static_cast<unsigned char>(*a)) != std::tolower(static_cast<unsigned char>(*b))) return false;
    ++a, ++b;
  }
}

std::int64_t timeval_ns(const timeval& tv) {
  return std::int64_t{tv.tv_sec} * 1'000'000'000 + std::int64_t{tv.tv_usec} * 1000;
}

}  // namespace

V4l2Camera::V4l2Camera(std::string device_path, CameraSettings settings)
    : StreamingCamera("v4l2", std::move(device_path), std::move(settings)) {}

V4l2Camera::~V4l2Camera() { release_device(); }

std::string V4l2Camera::open() {
  close();
  problem_.clear();
  if (settings_.buffer_count < 2 || settings_.buffer_count > kMaxBuffers)
    return "v4l2:" + name_ + ": buffer count " + std::to_string(settings_.buffer_count) + " is not in 2.." +
           std::to_string(kMaxBuffers);
  if (!bring_up()) {
    state_ = DeviceState::closed;
    return problem_.str();
  }
  char rate[32];
  if (fps_obtained_ > 0)
    std::snprintf(rate, sizeof rate, "%.3g fps", fps_obtained_);
  else
    std::snprintf(rate, sizeof rate, "rate set by device");
  description_ = "v4l2:" + name_ + " (" + driver_ + ", " + card_ + ") " + std::to_string(width_) + "x" +
                 std::to_string(height_) + " " + fourcc_text(fourcc_).text + " " + rate + ", " +
                 std::to_string(buffer_count_) + " buffers";
  if (!notes_.empty()) description_ += std::string("; ") + notes_.c_str();
  return "";
}

void V4l2Camera::close() {
  release_device();
  state_ = DeviceState::closed;
}

bool V4l2Camera::bring_up() {
  state_ = DeviceState::opening;
  notes_.clear();
  const int r = device_.open(name_.c_str());
  if (r < 0) {
    problem_.set("v4l2:%s: cannot open: %s (%s)", name_.c_str(), errno_name(r), std::strerror(-r));
    return false;
  }
  if (!check_capabilities()) return release_device(), false;
  state_ = DeviceState::configuring;
  if (!negotiate_format() || !set_frame_rate() || !apply_controls() || !map_buffers() || !start_stream())
    return release_device(), false;
  state_ = DeviceState::streaming;
  return true;
}

bool V4l2Camera::check_capabilities() {
  v4l2_capability cap{};
  const int r = device_.ioctl(VIDIOC_QUERYCAP, &cap);
  if (r < 0) {
    problem_.set("v4l2:%s: not a V4L2 device (VIDIOC_QUERYCAP: %s)", name_.c_str(), errno_name(r));
    return false;
  }
  std::snprintf(card_, sizeof card_, "%s", reinterpret_cast<const char*>(cap.card));
  std::snprintf(driver_, sizeof driver_, "%s", reinterpret_cast<const char*>(cap.driver));
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) {
    problem_.set("v4l2:%s: %s is not a single-planar video capture device%s", name_.c_str(), card_,
                 (caps & V4L2_CAP_VIDEO_CAPTURE_MPLANE) ? " (multi-planar only: not supported)" : "");
    return false;
  }
  if (!(caps & V4L2_CAP_STREAMING)) {
    problem_.set("v4l2:%s: %s cannot stream (no V4L2_CAP_STREAMING; read() devices are not supported)", name_.c_str(),
                 card_);
    return false;
  }
  return true;
}

bool V4l2Camera::negotiate_format() {
  // What the device offers, to choose from and to name when nothing fits.
  std::uint32_t offered[32];
  int n_offered = 0;
  for (std::uint32_t i = 0; n_offered < 32; ++i) {
    v4l2_fmtdesc d{};
    d.index = i;
    d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (device_.ioctl(VIDIOC_ENUM_FMT, &d) < 0) break;
    offered[n_offered++] = d.pixelformat;
  }
  char offered_text[200] = "";
  for (int i = 0, at = 0; i < n_offered && at < static_cast<int>(sizeof offered_text) - 8; ++i)
    at += std::snprintf(offered_text + at, sizeof offered_text - static_cast<std::size_t>(at), "%s%s", i ? ", " : "",
                        fourcc_text(offered[i]).text);

  // After the first bring-up the frame pool is sized for format(): a reopen keeps it.
  const FormatChoice* chosen = nullptr;
  const FormatChoice* grey_choice = nullptr;  // YUYV from here is reduced to its Y plane
  const char* wanted = nullptr;
  const bool colour_allowed =
      settings_.colour != ColourCapture::grey && (!format_locked_ || format_ == PixelFormat::rgb8);
  const bool grey_allowed =
      settings_.colour != ColourCapture::colour && (!format_locked_ || format_ == PixelFormat::mono8);
  if (settings_.format == PixelFormat::mono16) {
    chosen = first_offered(kMono16Choices, offered, n_offered);
    wanted = "Y16, Y16 big-endian, Y12 or Y10";
  } else {
    if (colour_allowed) chosen = first_offered(kColourChoices, offered, n_offered);
    if (!chosen && grey_allowed) chosen = grey_choice = first_offered(kMono8Choices, offered, n_offered);
    wanted = !colour_allowed ? "GREY, YUYV or UYVY"
             : !grey_allowed ? "colour (RGB3, BGR3, YUYV, UYVY or 8-bit Bayer)"
                             : "GREY or colour (RGB3, BGR3, YUYV, UYVY or 8-bit Bayer)";
  }
  if (!chosen) {
    problem_.set("v4l2:%s: %s offers no %s format (it offers: %s)", name_.c_str(), card_, wanted,
                 n_offered ? offered_text : "nothing");
    return false;
  }
  const PixelFormat delivered = settings_.format == PixelFormat::mono16 ? PixelFormat::mono16
                                : colour_allowed && is_colour_wire(chosen->wire) && chosen != grey_choice
                                    ? PixelFormat::rgb8
                                    : PixelFormat::mono8;
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<std::uint32_t>(settings_.width);
  fmt.fmt.pix.height = static_cast<std::uint32_t>(settings_.height);
  fmt.fmt.pix.pixelformat = chosen->fourcc;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  const int r = device_.ioctl(VIDIOC_S_FMT, &fmt);
  if (r < 0) {
    problem_.set("v4l2:%s: VIDIOC_S_FMT %dx%d %s failed: %s", name_.c_str(), settings_.width, settings_.height,
                 fourcc_text(chosen->fourcc).text, errno_name(r));
    return false;
  }
  // S_FMT adjusts rather than fails: compare what we got with what we asked.
  if (fmt.fmt.pix.pixelformat != chosen->fourcc || static_cast<int>(fmt.fmt.pix.width) != settings_.width ||
      static_cast<int>(fmt.fmt.pix.height) != settings_.height) {
    problem_.set("v4l2:%s: asked for %dx%d %s, %s offers %ux%u %s instead (formats: %s)", name_.c_str(),
                 settings_.width, settings_.height, fourcc_text(chosen->fourcc).text, card_, fmt.fmt.pix.width,
                 fmt.fmt.pix.height, fourcc_text(fmt.fmt.pix.pixelformat).text, offered_text);
    return false;
  }
  if (fmt.fmt.pix.field != V4L2_FIELD_NONE && fmt.fmt.pix.field != V4L2_FIELD_ANY) {
    problem_.set("v4l2:%s: %s delivers interlaced frames (field %u): not supported", name_.c_str(), card_,
                 fmt.fmt.pix.field);
    return false;
  }
  width_ = settings_.width;
  height_ = settings_.height;
  format_ = delivered;
  format_locked_ = true;
  fourcc_ = chosen->fourcc;
  wire_ = chosen->wire;
  significant_bits_ = chosen->significant_bits;
  const std::ptrdiff_t min_line = std::ptrdiff_t{width_} * wire_bytes_per_pixel(wire_);
  bytes_per_line_ = fmt.fmt.pix.bytesperline ? static_cast<std::ptrdiff_t>(fmt.fmt.pix.bytesperline) : min_line;
  size_image_ = fmt.fmt.pix.sizeimage;
  if (bytes_per_line_ < min_line ||
      size_image_ < static_cast<std::size_t>(bytes_per_line_ * (height_ - 1) + min_line)) {
    problem_.set("v4l2:%s: device reports %td bytes per line and %zu per image for %dx%d %s: too small", name_.c_str(),
                 bytes_per_line_, size_image_, width_, height_, fourcc_text(fourcc_).text);
    return false;
  }
  return true;
}

bool V4l2Camera::set_frame_rate() {
  fps_obtained_ = 0;
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (device_.ioctl(VIDIOC_G_PARM, &parm) < 0 || !(parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
    if (settings_.fps > 0) notes_.append("no frame rate control: the device sets the rate");
    return true;
  }
  if (settings_.fps > 0) {
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(std::lround(settings_.fps * 1000));
    const int r = device_.ioctl(VIDIOC_S_PARM, &parm);
    if (r < 0) {
      problem_.set("v4l2:%s: VIDIOC_S_PARM %.3g fps failed: %s", name_.c_str(), settings_.fps, errno_name(r));
      return false;
    }
  }
  const auto& tpf = parm.parm.capture.timeperframe;
  if (tpf.numerator > 0 && tpf.denominator > 0) fps_obtained_ = double(tpf.denominator) / tpf.numerator;
  if (settings_.fps > 0 && std::abs(fps_obtained_ - settings_.fps) > 0.01 * settings_.fps) {
    problem_.set("v4l2:%s: asked for %.3g fps, %s gives %.3g fps", name_.c_str(), settings_.fps, card_, fps_obtained_);
    return false;
  }
  return true;
}

bool V4l2Camera::find_control(std::uint32_t id, const char* name, v4l2_queryctrl& out) const {
  if (id != 0) {
    out = v4l2_queryctrl{};
    out.id = id;
    if (device_.ioctl(VIDIOC_QUERYCTRL, &out) == 0 && !(out.flags & V4L2_CTRL_FLAG_DISABLED)) return true;
    if (name == nullptr) return false;
  }
  v4l2_queryctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
  while (device_.ioctl(VIDIOC_QUERYCTRL, &q) == 0) {
    if (!(q.flags & V4L2_CTRL_FLAG_DISABLED) && q.type != V4L2_CTRL_TYPE_CTRL_CLASS &&
        same_control_name(reinterpret_cast<const char*>(q.name), name)) {
      out = q;
      return true;
    }
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
  }
  return false;
}

// 0, or -errno with problem_ set.
int V4l2Camera::write_control(const v4l2_queryctrl& ctrl, double value, const char* what) {
  const char* name = reinterpret_cast<const char*>(ctrl.name);
  if (ctrl.flags & (V4L2_CTRL_FLAG_READ_ONLY | V4L2_CTRL_FLAG_GRABBED)) {
    problem_.set("v4l2:%s: control \"%s\" (%s) is read-only now", name_.c_str(), name, what);
    return -EACCES;
  }
  const double v = std::round(value);
  if (v < ctrl.minimum || v > ctrl.maximum) {
    problem_.set("v4l2:%s: %s %g is outside \"%s\" range %d..%d", name_.c_str(), what, value, name, ctrl.minimum,
                 ctrl.maximum);
    return -ERANGE;
  }
  v4l2_control c{};
  c.id = ctrl.id;
  c.value = static_cast<std::int32_t>(v);
  const int r = device_.ioctl(VIDIOC_S_CTRL, &c);
  if (r < 0) problem_.set("v4l2:%s: setting \"%s\" to %d failed: %s", name_.c_str(), name, c.value, errno_name(r));
  return r < 0 ? r : 0;
}

bool V4l2Camera::apply_controls() {
  v4l2_queryctrl q{};
  if (settings_.exposure_us) {
    // Absolute exposure is in units of 100 us; it only applies with auto exposure off.
    if (find_control(V4L2_CID_EXPOSURE_ABSOLUTE, nullptr, q)) {
      v4l2_queryctrl automatic{};
      if (find_control(V4L2_CID_EXPOSURE_AUTO, nullptr, automatic) &&
          write_control(automatic, V4L2_EXPOSURE_MANUAL, "manual exposure") < 0)
        return false;
      if (write_control(q, *settings_.exposure_us / 100.0, "exposure (100 us units)") < 0) return false;
    } else {
      notes_.append("no exposure control: exposure left to the device");
    }
  }
  if (settings_.gain) {
    if (find_control(V4L2_CID_GAIN, nullptr, q) || find_control(V4L2_CID_ANALOGUE_GAIN, nullptr, q)) {
      if (write_control(q, *settings_.gain, "gain") < 0) return false;
    } else {
      notes_.append("no gain control: gain left to the device");
    }
  }
  for (const auto& [name, text] : settings_.controls) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0') {
      problem_.set("v4l2:%s: control \"%s\": value \"%s\" is not a number", name_.c_str(), name.c_str(), text.c_str());
      return false;
    }
    if (!find_control(0, name.c_str(), q)) {
      problem_.set("v4l2:%s: %s has no control \"%s\"", name_.c_str(), card_, name.c_str());
      return false;
    }
    if (write_control(q, value, name.c_str()) < 0) return false;
  }
  return true;
}

std::string V4l2Camera::set_control(const std::string& name, const std::string& value) {
  if (!device_.is_open()) return "v4l2:" + name_ + ": not open";
  // Apply this one control alone, then remember it for the next bring-up.
  CameraSettings saved = settings_;
  settings_.exposure_us.reset();
  settings_.gain.reset();
  settings_.controls.assign(1, {name, value});
  const bool ok = apply_controls();
  settings_ = std::move(saved);
  if (!ok) return problem_.str();
  settings_.controls.emplace_back(name, value);
  return "";
}

bool V4l2Camera::map_buffers() {
  v4l2_requestbuffers req{};
  req.count = static_cast<std::uint32_t>(settings_.buffer_count);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  int r = device_.ioctl(VIDIOC_REQBUFS, &req);
  if (r < 0) {
    problem_.set("v4l2:%s: VIDIOC_REQBUFS (%d mmap buffers) failed: %s", name_.c_str(), settings_.buffer_count,
                 errno_name(r));
    return false;
  }
  if (req.count < 2 || req.count > kMaxBuffers) {
    problem_.set("v4l2:%s: device granted %u buffers (need 2..%d)", name_.c_str(), req.count, kMaxBuffers);
    buffer_count_ = 0;
    return false;
  }
  buffer_count_ = static_cast<int>(req.count);
  for (int i = 0; i < buffer_count_; ++i) {
    v4l2_buffer b{};
    b.index = static_cast<std::uint32_t>(i);
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    r = device_.ioctl(VIDIOC_QUERYBUF, &b);
    if (r < 0) {
      problem_.set("v4l2:%s: VIDIOC_QUERYBUF %d failed: %s", name_.c_str(), i, errno_name(r));
      return false;
    }
    if (b.length < size_image_) {
      problem_.set("v4l2:%s: buffer %d holds %u bytes, an image needs %zu", name_.c_str(), i, b.length, size_image_);
      return false;
    }
    void* p = mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, device_.fd(), b.m.offset);
    if (p == MAP_FAILED) {
      problem_.set("v4l2:%s: mmap of buffer %d failed: %s", name_.c_str(), i, std::strerror(errno));
      return false;
    }
    buffers_[static_cast<std::size_t>(i)] = {p, b.length};
  }
  return true;
}

bool V4l2Camera::start_stream() {
  for (int i = 0; i < buffer_count_; ++i) {
    v4l2_buffer b{};
    b.index = static_cast<std::uint32_t>(i);
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    const int r = device_.ioctl(VIDIOC_QBUF, &b);
    if (r < 0) {
      problem_.set("v4l2:%s: VIDIOC_QBUF %d failed: %s", name_.c_str(), i, errno_name(r));
      return false;
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  const int r = device_.ioctl(VIDIOC_STREAMON, &type);
  if (r < 0) {
    problem_.set("v4l2:%s: VIDIOC_STREAMON failed: %s", name_.c_str(), errno_name(r));
    return false;
  }
  streaming_ = true;
  have_sequence_ = false;  // the device counts from 0 again
  last_frame_ns_ = monotonic_ns();
  return true;
}

bool V4l2Camera::restart_stream() {
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  const int r = device_.ioctl(VIDIOC_STREAMOFF, &type);  // also takes back every queued buffer
  streaming_ = false;
  if (r < 0) {
    lose_device(r, "VIDIOC_STREAMOFF after a stall");
    return false;
  }
  if (!start_stream()) {
    release_device();
    state_ = DeviceState::recovering;
    backoff_.start(monotonic_ns());
    return false;
  }
  ++counters_.reconnects;
  return true;
}

void V4l2Camera::lose_device(int neg_errno, const char* during) {
  problem_.set("v4l2:%s: %s during %s: %s (%s); reopening", name_.c_str(),
               device_gone(neg_errno) ? "device lost" : "stream failed", during, errno_name(neg_errno),
               std::strerror(-neg_errno));
  release_device();
  state_ = DeviceState::recovering;
  backoff_.start(monotonic_ns());
}

void V4l2Camera::release_device() {
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    (void)device_.ioctl(VIDIOC_STREAMOFF, &type);  // fails harmlessly on a vanished device
    streaming_ = false;
  }
  for (int i = 0; i < kMaxBuffers; ++i) {
    Mapped& m = buffers_[static_cast<std::size_t>(i)];
    if (m.start) munmap(m.start, m.length);
    m = Mapped{};
  }
  if (buffer_count_ > 0 && device_.is_open()) {
    v4l2_requestbuffers req{};
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    (void)device_.ioctl(VIDIOC_REQBUFS, &req);  // count 0: the driver frees its buffers
  }
  buffer_count_ = 0;
  device_.close();
}

void V4l2Camera::on_stall() {
  problem_.set("v4l2:%s: no frame for %d ms: stream restarted", name_.c_str(), settings_.effective_stall_timeout_ms());
  restart_stream();
}

std::optional<CaptureStatus> V4l2Camera::wait_for_frame(const MutableImageView& into, FrameMeta& meta, std::int64_t now,
                                                        std::int64_t wake) {
  pollfd p{device_.fd(), POLLIN, 0};
  const int wait_ms = static_cast<int>(std::max<std::int64_t>(0, (wake - now + 999'999) / 1'000'000));
  const int r = ::poll(&p, 1, wait_ms);
  if (r < 0 && errno != EINTR) {
    lose_device(-errno, "poll");
    return std::nullopt;
  }
  if (r > 0) {
    const CaptureStatus s = dequeue(into, meta);
    if (s != CaptureStatus::timeout) return s;  // timeout here: nothing was ready after all
  }
  return std::nullopt;
}

CaptureStatus V4l2Camera::dequeue(const MutableImageView& into, FrameMeta& meta) {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  int r = device_.ioctl(VIDIOC_DQBUF, &b);
  if (r == -EAGAIN) return CaptureStatus::timeout;
  if (r < 0) {
    // Gone, or in a state only a fresh open clears (e.g. EINVAL after a failed restart).
    lose_device(r, "VIDIOC_DQBUF");
    return CaptureStatus::recovering;
  }
  const std::int64_t now = monotonic_ns();
  if (b.index >= static_cast<std::uint32_t>(buffer_count_)) {
    problem_.set("v4l2:%s: device returned buffer %u of %d", name_.c_str(), b.index, buffer_count_);
    lose_device(-EPROTO, "VIDIOC_DQBUF");
    return CaptureStatus::recovering;
  }
  if (have_sequence_) {
    const std::uint32_t gap = b.sequence - last_sequence_ - 1;  // modulo 2^32
    if (gap > 0 && gap < 0x8000'0000u) counters_.dropped += gap;
  }
  have_sequence_ = true;
  last_sequence_ = b.sequence;
  last_frame_ns_ = now;

  const Mapped& m = buffers_[b.index];
  const std::size_t used = b.bytesused ? std::min<std::size_t>(b.bytesused, m.length) : size_image_;
  CaptureStatus status = CaptureStatus::frame;
  if (b.flags & V4L2_BUF_FLAG_ERROR) {
    problem_.set("v4l2:%s: frame %u flagged as damaged by the device", name_.c_str(), b.sequence);
    status = CaptureStatus::error;
  } else if (!convert_frame(static_cast<const std::uint8_t*>(m.start), bytes_per_line_, used, wire_, into)) {
    problem_.set("v4l2:%s: frame %u is short: %zu bytes", name_.c_str(), b.sequence, used);
    status = CaptureStatus::error;
  } else {
    meta.sequence = b.sequence;
    // A monotonic driver timestamp is when the frame was captured; otherwise the best we
    // have is now, which includes the driver's and our latency.
    meta.t_ns =
        (b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC ? timeval_ns(b.timestamp) : now;
    meta.gyro.reset();
  }
  r = device_.ioctl(VIDIOC_QBUF, &b);
  if (r < 0) {
    lose_device(r, "VIDIOC_QBUF");
    if (status == CaptureStatus::frame) {
      ++counters_.frames;
      return status;  // this frame is good; recovery starts on the next call
    }
  }
  return counted(status);
}

}  // namespace ccdlane
