// An example lane departure warning consumer: the reference for integrating ccdlaned.
// It subscribes to the lane channel and prints one line whenever ccdlaned's LDW state
// changes: available or not (and why, for the driver's display), and each warning with
// its side, the front wheel's distance to the line (DLC) and the time to crossing (TLC).
// The decision is ccdlaned's (ISO 17361 warning lines, suppression by speed and turn
// indicator, one warning per departure): a consumer shows it and adds no threshold.
//
// Needs only LCM and the generated headers the ccdlane package installs:
//   g++ -std=c++17 ldw_consumer.cpp -o ldw_consumer $(pkg-config --cflags --libs lcm)
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <ccdlane/lane_estimate_t.hpp>
#include <lcm/lcm-cpp.hpp>

namespace {

using Lane = ccdlane::lane_estimate_t;

struct Options {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";  // ccdlaned's default [lcm] url
  std::string channel = "CCDLANE_LANES";                // [lcm] prefix + LANES
  long count = 0;                                       // stop after this many messages; 0 = run until killed
};

const char* side_name(std::int8_t warning) {
  return warning == Lane::WARNING_LEFT ? "left" : warning == Lane::WARNING_RIGHT ? "right" : "none";
}

const char* reason_name(std::int8_t reason) {
  switch (reason) {
    case Lane::LDW_REASON_NONE: return "none";
    case Lane::LDW_REASON_CAMERA_FAULT: return "camera fault";
    case Lane::LDW_REASON_GYRO_FAULT: return "gyro fault";
    case Lane::LDW_REASON_NOT_CALIBRATED: return "not calibrated";
    case Lane::LDW_REASON_NO_LANE: return "no lane";
    case Lane::LDW_REASON_TOO_SLOW: return "too slow";
    case Lane::LDW_REASON_VEHICLE_FAULT: return "vehicle fault";
    default: return "unknown";
  }
}

class Warner {
 public:
  long received = 0;

  void on_lane(const lcm::ReceiveBuffer*, const std::string&, const Lane* m) {
    ++received;
    const long long frame = static_cast<long long>(m->frame);
    const bool available = m->ldw_available != 0;
    if (received == 1 || available != available_ || (!available && m->ldw_reason != reason_)) {
      if (available)
        std::printf("frame %lld: LDW available\n", frame);
      else
        std::printf("frame %lld: LDW unavailable: %s\n", frame, reason_name(m->ldw_reason));
      available_ = available;
      reason_ = m->ldw_reason;
    }
    // ldw_fired marks the frame a departure's warning starts; ldw_warning stays set for
    // a while after (for a chime or a display), then clears.
    if (m->ldw_fired != Lane::WARNING_NONE) {
      const bool left = m->ldw_fired == Lane::WARNING_LEFT;
      const double dlc = left ? m->dlc_left_mm : m->dlc_right_mm;
      const double tlc = left ? m->tlc_left_s : m->tlc_right_s;
      std::printf("frame %lld: WARNING %s: wheel %.0f mm from the line", frame, side_name(m->ldw_fired), dlc);
      if (std::isfinite(tlc)) std::printf(", crossing in %.2f s", tlc);
      std::printf(" (lateral %.2f m/s)\n", m->lateral_velocity_mps);
    } else if (m->ldw_warning == Lane::WARNING_NONE && warning_ != Lane::WARNING_NONE) {
      std::printf("frame %lld: clear\n", frame);
    }
    warning_ = m->ldw_warning;
    std::fflush(stdout);
  }

 private:
  bool available_ = false;
  std::int8_t reason_ = Lane::LDW_REASON_NONE;
  std::int8_t warning_ = Lane::WARNING_NONE;
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
    if (!value) return false;
    if (arg == "--lcm")
      o.url = value;
    else if (arg == "--channel")
      o.channel = value;
    else if (arg == "--count")
      o.count = std::atol(value);
    else
      return false;
    ++i;
  }
  return o.count >= 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr, "usage: %s [--lcm URL] [--channel CCDLANE_LANES] [--count N]\n", argv[0]);
    return 2;
  }
  lcm::LCM bus(o.url);
  if (!bus.good()) {
    std::fprintf(stderr, "ldw_consumer: cannot open the LCM bus %s\n", o.url.c_str());
    return 1;
  }
  Warner warner;
  bus.subscribe(o.channel, &Warner::on_lane, &warner);
  std::fprintf(stderr, "ldw_consumer: listening on %s at %s\n", o.channel.c_str(), o.url.c_str());
  while ((o.count == 0 || warner.received < o.count) && bus.handle() == 0) {
  }
  return 0;
}
