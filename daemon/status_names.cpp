// Indexed by the constants of status_t.lcm, checked against them at compile time.
#include "daemon/status_names.hpp"

#include <ccdlane/status_t.hpp>

namespace ccdlane {
namespace {

constexpr const char* kCameraStates[] = {"starting", "streaming", "stalled", "recovering", "ended"};
constexpr const char* kGyroStates[] = {"none", "starting", "ok", "stale", "lost"};
static_assert(status_t::CAMERA_ENDED + 1 == sizeof kCameraStates / sizeof kCameraStates[0]);
static_assert(status_t::GYRO_LOST + 1 == sizeof kGyroStates / sizeof kGyroStates[0]);

template <int N>
const char* name_of(const char* const (&names)[N], int code) {
  return code >= 0 && code < N ? names[code] : "unknown";
}

}  // namespace

const char* camera_state_name(int code) { return name_of(kCameraStates, code); }
const char* gyro_state_name(int code) { return name_of(kGyroStates, code); }

}  // namespace ccdlane
