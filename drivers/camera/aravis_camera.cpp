// The Aravis camera. GObject calls stay in this file; errors become one line in a fixed
// buffer so the streaming path never allocates.
#include "drivers/camera/aravis_camera.hpp"

#include <arv.h>

#include <cmath>
#include <cstring>

namespace ccdlane {
namespace {

struct GenicamFormatChoice {
  const char* name;
  ArvPixelFormat code;
  WirePixels wire;
  int significant_bits;
};
constexpr GenicamFormatChoice kGenicamMono8Choices[] = {{"Mono8", ARV_PIXEL_FORMAT_MONO_8, WirePixels::mono8, 8}};
// Full-resolution colour first; the 2x2 demosaic of Bayer after. PFNC names Bayer by the
// top-left cell: BayerRG8 is R G / G B.
constexpr GenicamFormatChoice kGenicamColourChoices[] = {
    {"RGB8", ARV_PIXEL_FORMAT_RGB_8_PACKED, WirePixels::rgb24, 8},
    {"BGR8", ARV_PIXEL_FORMAT_BGR_8_PACKED, WirePixels::bgr24, 8},
    {"BayerRG8", ARV_PIXEL_FORMAT_BAYER_RG_8, WirePixels::bayer_rggb, 8},
    {"BayerBG8", ARV_PIXEL_FORMAT_BAYER_BG_8, WirePixels::bayer_bggr, 8},
    {"BayerGR8", ARV_PIXEL_FORMAT_BAYER_GR_8, WirePixels::bayer_grbg, 8},
    {"BayerGB8", ARV_PIXEL_FORMAT_BAYER_GB_8, WirePixels::bayer_gbrg, 8},
};

// The first of `choices` among the camera's `available` names (only `only` when that is
// not empty), or null.
template <std::size_t N>
const GenicamFormatChoice* first_available(const GenicamFormatChoice (&choices)[N], const char* const* available, guint n,
                                    const std::string& only) {
  for (const GenicamFormatChoice& c : choices)
    if (only.empty() || only == c.name)
      for (guint i = 0; i < n; ++i)
        if (available[i] && std::strcmp(available[i], c.name) == 0) return &c;
  return nullptr;
}
// Unpacked 16-bit containers, little endian on the wire (GenICam PFNC).
constexpr GenicamFormatChoice kGenicamMono16Choices[] = {
    {"Mono16", ARV_PIXEL_FORMAT_MONO_16, WirePixels::mono16_le, 16},
    {"Mono12", ARV_PIXEL_FORMAT_MONO_12, WirePixels::mono16_le, 12},
    {"Mono10", ARV_PIXEL_FORMAT_MONO_10, WirePixels::mono16_le, 10},
};

const char* status_name(ArvBufferStatus s) {
  switch (s) {
    case ARV_BUFFER_STATUS_SUCCESS: return "success";
    case ARV_BUFFER_STATUS_CLEARED: return "cleared";
    case ARV_BUFFER_STATUS_TIMEOUT: return "timeout";
    case ARV_BUFFER_STATUS_MISSING_PACKETS: return "missing packets";
    case ARV_BUFFER_STATUS_WRONG_PACKET_ID: return "wrong packet id";
    case ARV_BUFFER_STATUS_SIZE_MISMATCH: return "size mismatch";
    case ARV_BUFFER_STATUS_FILLING: return "filling";
    case ARV_BUFFER_STATUS_ABORTED: return "aborted";
    default: return "unknown status";
  }
}

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

// Frames missing between two ids. GigE Vision 1.x ids are 16 bits and skip 0 when they
// wrap; anything else going backwards is a restart, not a loss.
std::uint64_t frames_between(std::uint64_t last, std::uint64_t id) {
  if (id > last) return id - last - 1;
  if (last >= 0xff00 && last <= 0xffff && id < 0x100) return (0xffff - last) + (id - 1);
  return 0;
}

}  // namespace

AravisCamera::AravisCamera(std::string id, CameraSettings settings)
    : StreamingCamera("aravis", std::move(id), std::move(settings)) {}

AravisCamera::~AravisCamera() { release_camera(true); }

void AravisCamera::on_control_lost(ArvDevice*, void* self) {
  static_cast<AravisCamera*>(self)->control_lost_.store(true, std::memory_order_release);
}

std::string AravisCamera::open() {
  close();
  problem_.clear();
  if (settings_.buffer_count < 2 || settings_.buffer_count > 64)
    return "aravis:" + name_ + ": buffer count " + std::to_string(settings_.buffer_count) + " is not in 2..64";
  if (name_.rfind("Fake", 0) == 0) arv_enable_interface("Fake");
  if (!bring_up()) {
    state_ = DeviceState::closed;
    return problem_.str();
  }
  const char* vendor = arv_camera_get_vendor_name(camera_, nullptr);
  const char* model = arv_camera_get_model_name(camera_, nullptr);
  const char* serial = arv_camera_get_device_serial_number(camera_, nullptr);
  const char* transport = arv_camera_is_gv_device(camera_)   ? "GigE Vision"
                          : arv_camera_is_uv_device(camera_) ? "USB3 Vision"
                                                             : "Aravis";
  char text[256];
  std::snprintf(text, sizeof text, "aravis:%s (%s %s, serial %s, %s", name_.c_str(), vendor ? vendor : "?",
                model ? model : "?", serial ? serial : "?", transport);
  description_ = text;
  if (packet_size_ > 0) description_ += ", packets of " + std::to_string(packet_size_) + " B";
  std::snprintf(text, sizeof text, ") %dx%d %s %.4g fps, %d buffers", width_, height_,
                arv_camera_get_pixel_format_as_string(camera_, nullptr), fps_obtained_, settings_.buffer_count);
  description_ += text;
  if (!notes_.empty()) description_ += std::string("; ") + notes_.c_str();
  return "";
}

void AravisCamera::close() {
  release_camera(!control_lost_.load());
  state_ = DeviceState::closed;
}

bool AravisCamera::bring_up() {
  state_ = DeviceState::opening;
  notes_.clear();
  control_lost_ = false;
  GError* error = nullptr;
  camera_ = arv_camera_new(name_.c_str(), &error);
  if (camera_ == nullptr) {
    problem_.set("aravis:%s: cannot open: %s", name_.c_str(), error ? error->message : "no such camera");
    g_clear_error(&error);
    return false;
  }
  g_signal_connect(arv_camera_get_device(camera_), "control-lost", G_CALLBACK(on_control_lost), this);
  state_ = DeviceState::configuring;
  if (!configure() || !start_stream()) {
    release_camera(true);
    return false;
  }
  state_ = DeviceState::streaming;
  return true;
}

// Sets one feature from text, whatever its type. false with problem_ set.
bool AravisCamera::set_feature(const char* name, const char* value) {
  char assignment[256];
  std::snprintf(assignment, sizeof assignment, "%s=%s", name, value);
  GError* error = nullptr;
  if (!arv_camera_is_feature_available(camera_, name, nullptr)) {
    problem_.set("aravis:%s: the camera has no feature %s", name_.c_str(), name);
    return false;
  }
  arv_device_set_features_from_string(arv_camera_get_device(camera_), assignment, &error);
  if (error) {
    problem_.set("aravis:%s: setting %s: %s", name_.c_str(), assignment, error->message);
    g_clear_error(&error);
    return false;
  }
  return true;
}

bool AravisCamera::configure() {
  GError* error = nullptr;
  auto failed = [&](const char* what) {
    if (!error) return false;
    problem_.set("aravis:%s: %s: %s", name_.c_str(), what, error->message);
    g_clear_error(&error);
    return true;
  };
  // A camera keeps its settings between clients (and may still be streaming for a
  // previous one): set every feature we rely on, from a stopped state.
  arv_camera_stop_acquisition(camera_, nullptr);
  arv_camera_set_acquisition_mode(camera_, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
  if (failed("AcquisitionMode=Continuous")) return false;
  if (arv_camera_is_feature_available(camera_, "TriggerMode", nullptr) && !set_feature("TriggerMode", "Off"))
    return false;

  const bool mono16 = settings_.format == PixelFormat::mono16;
  // After the first bring-up the frame pool is sized for format(): a reconnect keeps it.
  const bool colour_allowed =
      settings_.colour != ColourCapture::grey && (!format_locked_ || format_ == PixelFormat::rgb8);
  const bool grey_allowed =
      settings_.colour != ColourCapture::colour && (!format_locked_ || format_ == PixelFormat::mono8);
  guint n_available = 0;
  const char** available = arv_camera_dup_available_pixel_formats_as_strings(camera_, &n_available, nullptr);
  const GenicamFormatChoice* chosen = nullptr;
  if (mono16) {
    chosen = first_available(kGenicamMono16Choices, available, n_available, settings_.device_format);
  } else {
    if (colour_allowed) chosen = first_available(kGenicamColourChoices, available, n_available, settings_.device_format);
    if (!chosen && grey_allowed)
      chosen = first_available(kGenicamMono8Choices, available, n_available, settings_.device_format);
  }
  const char* wanted = !settings_.device_format.empty() ? settings_.device_format.c_str()
                       : mono16                         ? "Mono16, Mono12 or Mono10"
                       : !colour_allowed                ? "Mono8"
                       : !grey_allowed                  ? "colour (RGB8, BGR8 or 8-bit Bayer)"
                                                        : "Mono8 or colour (RGB8, BGR8 or 8-bit Bayer)";
  if (!chosen) {
    char offered[200] = "";
    for (guint i = 0, at = 0; i < n_available && at + 8 < sizeof offered; ++i)
      at += static_cast<guint>(std::snprintf(offered + at, sizeof offered - at, "%s%s", i ? ", " : "", available[i]));
    problem_.set("aravis:%s: no %s pixel format (the camera offers: %s)", name_.c_str(), wanted,
                 n_available ? offered : "nothing");
    g_free(available);
    return false;
  }
  g_free(available);
  arv_camera_set_pixel_format_from_string(camera_, chosen->name, &error);
  if (failed("PixelFormat")) return false;
  arv_format_ = chosen->code;
  wire_ = chosen->wire;
  format_ = pixel_format_of(chosen->wire);
  format_locked_ = true;
  significant_bits_ = chosen->significant_bits;

  arv_camera_set_region(camera_, 0, 0, settings_.width, settings_.height, &error);
  if (failed("Width/Height")) return false;
  gint x = 0, y = 0, w = 0, h = 0;
  arv_camera_get_region(camera_, &x, &y, &w, &h, &error);
  if (failed("reading Width/Height")) return false;
  if (w != settings_.width || h != settings_.height) {
    problem_.set("aravis:%s: asked for %dx%d, the camera gives %dx%d", name_.c_str(), settings_.width, settings_.height,
                 w, h);
    return false;
  }
  width_ = w;
  height_ = h;

  double lo = 0, hi = 0;
  arv_camera_get_frame_rate_bounds(camera_, &lo, &hi, nullptr);
  fps_max_ = hi;
  if (settings_.fps > 0) {
    arv_camera_set_frame_rate(camera_, settings_.fps, &error);  // also enables AcquisitionFrameRate
    if (failed("AcquisitionFrameRate")) return false;
    fps_obtained_ = arv_camera_get_frame_rate(camera_, &error);
    if (failed("reading AcquisitionFrameRate")) return false;
    if (std::abs(fps_obtained_ - settings_.fps) > 0.01 * settings_.fps) {
      problem_.set("aravis:%s: asked for %.4g fps, the camera gives %.4g fps (range %.4g..%.4g at %dx%d)",
                   name_.c_str(), settings_.fps, fps_obtained_, lo, hi, w, h);
      return false;
    }
  } else {
    fps_obtained_ = arv_camera_get_frame_rate(camera_, nullptr);
  }
  if (settings_.exposure_us) {
    if (arv_camera_is_exposure_auto_available(camera_, nullptr))
      arv_camera_set_exposure_time_auto(camera_, ARV_AUTO_OFF, nullptr);
    arv_camera_set_exposure_time(camera_, *settings_.exposure_us, &error);
    if (failed("ExposureTime")) return false;
  }
  if (settings_.gain) {
    if (arv_camera_is_gain_auto_available(camera_, nullptr)) arv_camera_set_gain_auto(camera_, ARV_AUTO_OFF, nullptr);
    arv_camera_set_gain(camera_, *settings_.gain, &error);
    if (failed("Gain")) return false;
  }
  for (const auto& [name, value] : settings_.controls)
    if (!set_feature(name.c_str(), value.c_str())) return false;

  packet_size_ = 0;
  if (arv_camera_is_gv_device(camera_)) {
    if (settings_.packet_size > 0) {
      arv_camera_gv_set_packet_size(camera_, settings_.packet_size, &error);
      if (failed("GevSCPSPacketSize")) return false;
      packet_size_ = settings_.packet_size;
    } else {
      packet_size_ = static_cast<int>(arv_camera_gv_auto_packet_size(camera_, &error));  // largest that gets through
      if (failed("negotiating the packet size")) return false;
    }
  }
  payload_ = arv_camera_get_payload(camera_, &error);
  if (failed("PayloadSize")) return false;
  return true;
}

bool AravisCamera::start_stream() {
  GError* error = nullptr;
  stream_ = arv_camera_create_stream(camera_, nullptr, nullptr, &error);
  if (stream_ == nullptr) {
    problem_.set("aravis:%s: cannot create the stream: %s", name_.c_str(), error ? error->message : "?");
    g_clear_error(&error);
    return false;
  }
  // Every buffer exists and is queued before acquisition starts: nothing is allocated
  // per frame on our side, and the stream never lacks a buffer at start.
  for (int i = 0; i < settings_.buffer_count; ++i) arv_stream_push_buffer(stream_, arv_buffer_new_allocate(payload_));
  arv_camera_start_acquisition(camera_, &error);
  if (error) {
    problem_.set("aravis:%s: AcquisitionStart: %s", name_.c_str(), error->message);
    g_clear_error(&error);
    return false;
  }
  have_frame_id_ = false;
  last_frame_ns_ = monotonic_ns();
  return true;
}

void AravisCamera::release_camera(bool camera_reachable) {
  if (camera_ && stream_ && camera_reachable) arv_camera_stop_acquisition(camera_, nullptr);
  if (stream_) {
    arv_stream_set_emit_signals(stream_, FALSE);
    // Join the receive thread here, from this thread. Once, after a stall under load, the
    // finalizer's join failed with "Resource deadlock avoided" (as if run on the receive
    // thread itself) and GLib aborted the daemon; stopping the thread first leaves the
    // finalizer nothing to join.
    arv_stream_stop_thread(stream_, TRUE);
    g_clear_object(&stream_);  // frees the stream and what buffers remain
  }
  if (camera_) {
    g_signal_handlers_disconnect_by_data(arv_camera_get_device(camera_), this);
    g_clear_object(&camera_);
  }
}

void AravisCamera::lose_camera(const char* why) {
  problem_.set("aravis:%s: %s; reopening", name_.c_str(), why);
  release_camera(false);
  state_ = DeviceState::recovering;
  backoff_.start(monotonic_ns());
}

std::string AravisCamera::set_control(const std::string& name, const std::string& value) {
  if (camera_ == nullptr) return "aravis:" + name_ + ": not open";
  if (!set_feature(name.c_str(), value.c_str())) return problem_.str();
  settings_.controls.emplace_back(name, value);
  return "";
}

void AravisCamera::on_stall() {
  char why[64];
  std::snprintf(why, sizeof why, "no frame for %d ms", settings_.effective_stall_timeout_ms());
  lose_camera(why);
}

std::optional<CaptureStatus> AravisCamera::wait_for_frame(const MutableImageView& into, FrameMeta& meta,
                                                          std::int64_t now, std::int64_t wake) {
  if (control_lost_.load(std::memory_order_acquire)) {
    lose_camera("control lost (no heartbeat answer)");
    return std::nullopt;
  }
  ArvBuffer* buffer =
      arv_stream_timeout_pop_buffer(stream_, static_cast<guint64>(std::max<std::int64_t>(0, (wake - now) / 1000)));
  if (buffer == nullptr) return std::nullopt;
  const std::int64_t popped = monotonic_ns();
  last_frame_ns_ = popped;
  const std::uint64_t id = arv_buffer_get_frame_id(buffer);
  if (have_frame_id_) counters_.dropped += frames_between(last_frame_id_, id);
  have_frame_id_ = true;
  last_frame_id_ = id;

  CaptureStatus status = CaptureStatus::frame;
  const ArvBufferStatus buffer_status = arv_buffer_get_status(buffer);
  std::size_t size = 0;
  const void* data = buffer_status == ARV_BUFFER_STATUS_SUCCESS ? arv_buffer_get_image_data(buffer, &size) : nullptr;
  if (buffer_status != ARV_BUFFER_STATUS_SUCCESS) {
    problem_.set("aravis:%s: frame %llu: %s", name_.c_str(), static_cast<unsigned long long>(id),
                 status_name(buffer_status));
    status = CaptureStatus::error;
  } else if (arv_buffer_get_image_width(buffer) != width_ || arv_buffer_get_image_height(buffer) != height_ ||
             arv_buffer_get_image_pixel_format(buffer) != arv_format_) {
    problem_.set("aravis:%s: frame %llu is %dx%d format 0x%08x, expected %dx%d 0x%08x", name_.c_str(),
                 static_cast<unsigned long long>(id), arv_buffer_get_image_width(buffer),
                 arv_buffer_get_image_height(buffer), arv_buffer_get_image_pixel_format(buffer), width_, height_,
                 arv_format_);
    status = CaptureStatus::error;
  } else if (!convert_frame(static_cast<const std::uint8_t*>(data),
                            std::ptrdiff_t{width_} * wire_bytes_per_pixel(wire_), size, wire_, into)) {
    problem_.set("aravis:%s: frame %llu is short: %zu bytes", name_.c_str(), static_cast<unsigned long long>(id), size);
    status = CaptureStatus::error;
  } else {
    meta.sequence = id;
    // Aravis stamps a frame with the wall clock when its first packet arrives (its
    // "system timestamp"); we map that onto CLOCK_MONOTONIC with the offset between the
    // two clocks read now. Device timestamps are on the camera's own clock, not ours.
    const std::int64_t system_ns = static_cast<std::int64_t>(arv_buffer_get_system_timestamp(buffer));
    meta.t_ns = system_ns > 0 ? system_ns - (clock_ns(CLOCK_REALTIME) - clock_ns(CLOCK_MONOTONIC)) : popped;
    if (meta.t_ns > popped) meta.t_ns = popped;  // a wall-clock step must not put it in the future
    meta.gyro.reset();
  }
  arv_stream_push_buffer(stream_, buffer);  // back to the camera at once
  return counted(status);
}

}  // namespace ccdlane
