// An estimate errs high: a configuration refused here would have had less than the
// margin left for the rest of the machine.
#include "daemon/memory_estimate.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "app/synth_source.hpp"

namespace ccdlane {
namespace {

// Detection's lane-paint measure and its row buffers, the solver's pick buffers: a few
// floats per pixel at most.
constexpr std::uint64_t kEstimatorBytesPerPixel = 8;

std::uint64_t frame_bytes_per_pixel(const Config& c) {
  switch (c.source.kind) {
    case SourceKind::synth: return c.synth.bits > 8 ? 2 : 1;
    case SourceKind::frames: return 3;  // PNG frames may be colour, PGM 16-bit
    case SourceKind::video: return 3;   // colour, as decoded
    case SourceKind::v4l2:
    case SourceKind::aravis: return c.source.pixel_format == SourcePixels::grey ? 2 : 3;
  }
  return 3;
}

std::string mb(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f MB", static_cast<double>(bytes) / (1 << 20));
  return text;
}

}  // namespace

std::uint64_t estimated_start_bytes(const Config& c) {
  const std::uint64_t pixels = static_cast<std::uint64_t>(c.camera.Nu) * static_cast<std::uint64_t>(c.camera.Nv);
  const std::uint64_t frames = static_cast<std::uint64_t>(c.daemon.queue_depth) + 2;
  std::uint64_t bytes = frames * pixels * frame_bytes_per_pixel(c) + pixels * kEstimatorBytesPerPixel;
  if (c.source.kind == SourceKind::synth)
    bytes += static_cast<std::uint64_t>(synth_source_frame_count(c)) * pixels * frame_bytes_per_pixel(c);
  return bytes;
}

std::string memory_problem(const Config& c, std::uint64_t available_bytes) {
  const std::uint64_t need = estimated_start_bytes(c);
  if (need <= available_bytes / 2) return "";  // the rest of the machine keeps half
  return "needs an estimated " + mb(need) + " at start (daemon.queue_depth " + std::to_string(c.daemon.queue_depth) +
         " + 2 frames of " + std::to_string(c.camera.Nu) + "x" + std::to_string(c.camera.Nv) + " at " +
         std::to_string(frame_bytes_per_pixel(c)) + " bytes a pixel, and the estimator's workspaces" +
         (c.source.kind == SourceKind::synth ? ", and the rendered synthetic drive" : "") +
         "), more than half of the " + mb(available_bytes) +
         " this machine has; lower queue_depth or the camera's size";
}

std::uint64_t available_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  std::uint64_t bytes =
      pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : UINT64_MAX;
  rlimit as{};
  if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    bytes = std::min<std::uint64_t>(bytes, as.rlim_cur);
  return bytes;
}

}  // namespace ccdlane
