// An example lane departure warning consumer: the reference for integrating ccdlaned.
// It subscribes to the lane channel and prints one line whenever the warning state
// changes: WARNING when ccdlaned reports a departure or when a line of the vehicle's own
// lane comes within --warn-mm of the vehicle's centre; clear once it is back beyond
// --warn-mm + --hysteresis-mm (so a car riding the threshold does not chatter).
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

struct Options {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";  // ccdlaned's default [lcm] url
  std::string channel = "CCDLANE_LANES";                // [lcm] prefix + LANES
  double warn_mm = 1000.0;       // half a car (900 mm) plus a margin
  double hysteresis_mm = 150.0;
  long count = 0;                // stop after this many messages; 0 = run until killed
};

enum class Side { none, left, right };
const char* name(Side s) { return s == Side::left ? "left" : s == Side::right ? "right" : "none"; }
Side departure_side(std::int8_t departure) {
  if (departure == ccdlane::lane_estimate_t::DEPARTURE_LEFT) return Side::left;
  if (departure == ccdlane::lane_estimate_t::DEPARTURE_RIGHT) return Side::right;
  return Side::none;
}

class Warner {
 public:
  explicit Warner(const Options& o) : o_(o) {}
  long received = 0;

  void on_lane(const lcm::ReceiveBuffer*, const std::string&, const ccdlane::lane_estimate_t* m) {
    ++received;
    if (!m->ok) return;  // no estimate for this frame: keep the last state
    // The own lane's lines: the nearest with y0 > 0 (left) and with y0 < 0 (right).
    double left = INFINITY, right = INFINITY;
    for (int i = 0; i < m->num_lines && i < ccdlane::lane_estimate_t::MAX_LINES; ++i) {
      const double y0 = m->lines[i].y0_mm;
      if (y0 > 0) left = std::fmin(left, y0);
      if (y0 < 0) right = std::fmin(right, -y0);
    }
    Side next = departure_side(m->departure);  // ccdlaned's own verdict first
    if (next == Side::none && left < limit(Side::left)) next = Side::left;
    if (next == Side::none && right < limit(Side::right)) next = Side::right;
    if (next == state_) return;
    state_ = next;
    if (next == Side::none)
      std::printf("frame %lld: clear: lines %.0f mm left and %.0f mm right of the vehicle centre\n",
                  static_cast<long long>(m->frame), left, right);
    else
      std::printf("frame %lld: WARNING %s: %s line %.0f mm from the vehicle centre (departure: %s)\n",
                  static_cast<long long>(m->frame), name(next), name(next), next == Side::left ? left : right,
                  name(departure_side(m->departure)));
    std::fflush(stdout);
  }

 private:
  // Entering a warning takes warn_mm; leaving it takes warn_mm + hysteresis_mm.
  double limit(Side side) const { return o_.warn_mm + (state_ == side ? o_.hysteresis_mm : 0.0); }

  Options o_;
  Side state_ = Side::none;
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
    if (!value) return false;
    if (arg == "--lcm") o.url = value;
    else if (arg == "--channel") o.channel = value;
    else if (arg == "--warn-mm") o.warn_mm = std::atof(value);
    else if (arg == "--hysteresis-mm") o.hysteresis_mm = std::atof(value);
    else if (arg == "--count") o.count = std::atol(value);
    else return false;
    ++i;
  }
  return o.warn_mm > 0 && o.hysteresis_mm >= 0 && o.count >= 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr, "usage: %s [--lcm URL] [--channel CCDLANE_LANES] [--warn-mm 1000] "
                         "[--hysteresis-mm 150] [--count N]\n", argv[0]);
    return 2;
  }
  lcm::LCM bus(o.url);
  if (!bus.good()) {
    std::fprintf(stderr, "ldw_consumer: cannot open the LCM bus %s\n", o.url.c_str());
    return 1;
  }
  Warner warner(o);
  bus.subscribe(o.channel, &Warner::on_lane, &warner);
  std::fprintf(stderr, "ldw_consumer: listening on %s at %s\n", o.channel.c_str(), o.url.c_str());
  while ((o.count == 0 || warner.received < o.count) && bus.handle() == 0) {}
  return 0;
}
