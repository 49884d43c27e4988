// `ccdlane monitor`: watch ccdlaned on the bus: a compact line a second, or every lane
// message as the JSON object `ccdlane replay` prints for a frame (the same function
// prints both: the message is turned back into a LaneEstimate first).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include "app/config.hpp"
#include "bus/channels.hpp"
#include "bus/lane_message.hpp"
#include "bus/lcm_url.hpp"
#include "bus/status_names.hpp"
#include "tools/ccdlane/checked_output.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/json_output.hpp"
#include "tools/ccdlane/lane_estimate_json.hpp"
#include "tools/ccdlane/radius_text.hpp"

namespace ccdlane::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct MonitorArgs {
  std::string url = LcmConfig{}.url;
  std::string prefix = LcmConfig{}.prefix;
  long long count = 0;   // 0: no limit
  double seconds = 0.0;  // 0: no limit
  bool json = false;
};

class Monitor {
 public:
  explicit Monitor(const MonitorArgs& args)
      : args_(args),
        lanes_channel_(channel_name(args.prefix, Channel::lanes)),
        status_channel_(channel_name(args.prefix, Channel::status)),
        bus_(lcm_url_problem(args.url).empty() ? args.url : "memq://") {
    if (const std::string why = lcm_url_problem(args.url); !why.empty()) throw UsageError("--lcm: " + why);
    if (!bus_.good()) throw std::runtime_error("lcm: cannot open the bus \"" + args.url + "\"");
    // Plain functions, not subscribe(&Monitor::on_lane, this): GCC 12's UBSan reports a
    // false "invalid vptr" in LCM's member-function callback. An exception must not leave
    // a handler: it would unwind through LCM's C code, which then never returns the
    // message's buffer to its ring (standard output on a full disk once aborted the
    // process in lcm_ringbuf_dealloc instead of exiting 1). It is kept, and thrown once
    // handle returns.
    bus_.subscribeFunction(
        lanes_channel_,
        +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, Monitor* self) {
          self->handled([&] { self->on_lane(*m); });
        },
        this);
    bus_.subscribeFunction(
        status_channel_,
        +[](const lcm::ReceiveBuffer*, const std::string&, const status_t* m, Monitor* self) {
          self->handled([&] { self->on_status(*m); });
        },
        this);
  }

  int run() {
    const Clock::time_point start = Clock::now();
    const Clock::time_point deadline =
        args_.seconds > 0
            ? start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(args_.seconds))
            : Clock::time_point::max();
    Clock::time_point next_line = start + std::chrono::seconds(1);
    while (!done()) {
      const Clock::time_point now = Clock::now();
      if (now >= deadline) break;
      if (!args_.json && now >= next_line) {
        print_line();
        next_line += std::chrono::seconds(1);
      }
      const Clock::time_point wake = std::min(args_.json ? now + std::chrono::milliseconds(200) : next_line, deadline);
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(wake - now).count();
      if (bus_.handleTimeout(static_cast<int>(std::max<long long>(ms, 1))) < 0)
        throw std::runtime_error("lcm: receiving from \"" + args_.url + "\" failed");
      if (handler_failure_) std::rethrow_exception(handler_failure_);
    }
    if (!args_.json && lanes_ > lanes_printed_) print_line();
    if (lanes_ == 0) {
      std::cerr << "ccdlane: no lane messages on " << lanes_channel_ << " (" << args_.url << ")";
      if (args_.seconds > 0) std::cerr << " within " << args_.seconds << " s";
      std::cerr << '\n';
      return 1;
    }
    return 0;
  }

 private:
  bool done() const { return args_.count > 0 && lanes_ >= args_.count; }

  // Runs a handler's work; what it throws is kept for run() (see the constructor), and
  // nothing more is handled after it.
  template <typename Work>
  void handled(Work work) noexcept {
    if (handler_failure_) return;
    try {
      work();
    } catch (...) {
      handler_failure_ = std::current_exception();
    }
  }

  void on_lane(const lane_estimate_t& m) {
    if (done()) return;
    ++lanes_;
    ++lanes_in_second_;
    last_lane_ = m;
    if (args_.json) {
      print_json_line(std::cout, lane_estimate_json(from_message(m)));
      flush_checked(std::cout, "standard output");  // live through pipes, one object per message
    }
  }

  void on_status(const status_t& m) {
    last_status_ = m;
    if (args_.json && !done()) {
      print_json_line(std::cout, status_json(m));
      flush_checked(std::cout, "standard output");
    }
  }

  // --json: a status message as {"status": {...}}, so that it cannot be taken for a lane
  // message (those have no "status" key). The daemon's health is in the live line; here
  // what a script watching the mount's calibration needs.
  static Json status_json(const status_t& m) {
    Json calibration;
    calibration["state"] = calibration_state_name(m.calibration_state);
    calibration["progress"] = m.calibration_progress;
    calibration["yaw_deg"] = m.calibration_yaw_deg;
    calibration["pitch_deg"] = m.calibration_pitch_deg;
    calibration["yaw_estimate_deg"] = m.calibration_yaw_estimate_deg;
    calibration["pitch_estimate_deg"] = m.calibration_pitch_estimate_deg;
    calibration["yaw_sigma_deg"] = m.calibration_yaw_sigma_deg;
    calibration["pitch_sigma_deg"] = m.calibration_pitch_sigma_deg;
    calibration["frames"] = m.calibration_frames_total;
    Json status;
    status["utime"] = m.utime;
    status["instance"] = m.instance;
    status["camera"] = camera_state_name(m.camera_state);
    status["gyro"] = gyro_state_name(m.gyro_state);
    status["gyro_refused"] = m.gyro_refused_total;
    status["vehicle"] = vehicle_state_name(m.vehicle_state);
    Json refused = Json::object();
    for (int i = 0; i < 4; ++i) refused[vehicle_refusal_name(i)] = m.vehicle_refused_by_cause[i];
    status["vehicle_refused"] = refused;
    status["calibration"] = calibration;
    Json j;
    j["status"] = status;
    return j;
  }

  // "vehicle ok", or with refusals "vehicle fault (refused: speed 12, indicator 1)", and
  // the gyro's refused readings: what tells a broken gateway or gyro from a missing one.
  static void vehicle_words(const status_t& s, char* out, std::size_t size) {
    int n = std::snprintf(out, size, "vehicle %s", vehicle_state_name(s.vehicle_state));
    const char* open = " (refused:";
    for (int i = 0; i < 4 && n > 0 && static_cast<std::size_t>(n) < size; ++i) {
      if (s.vehicle_refused_by_cause[i] == 0) continue;
      n += std::snprintf(out + n, size - static_cast<std::size_t>(n), "%s %s %lld", open, vehicle_refusal_name(i),
                         static_cast<long long>(s.vehicle_refused_by_cause[i]));
      open = ",";
    }
    if (*open == ',' && n > 0 && static_cast<std::size_t>(n) < size)
      n += std::snprintf(out + n, size - static_cast<std::size_t>(n), ")");
    if (s.gyro_refused_total > 0 && n > 0 && static_cast<std::size_t>(n) < size)
      std::snprintf(out + n, size - static_cast<std::size_t>(n), ", gyro readings refused %lld",
                    static_cast<long long>(s.gyro_refused_total));
  }

  // "frame 1234 ok | psi 1.05 theta 0.71 phi -2.70 deg | lane 3601 mm, offset -49 mm,
  //  heading 0.07 deg, radius 850 m (straight at 10 km and beyond; - unsolved), departure none, tracking (or
  //  searching) | 30 msg/s | LDW
  //  available, warning none, DLC 910/905 mm, TLC -/1.84 s, lateral -0.05 m/s, heading 0.02 deg (mount yaw -1.36)
  //  (or LDW unavailable (too_slow)) | camera
  //  streaming, gyro ok, gyro reconnects 0, p99 1.2 ms, dropped 0, allocations 0" (no reconnect count without a gyro)
  void print_line() {
    char text[768];
    int n = 0;
    if (lanes_in_second_ == 0 || !last_lane_) {
      n = std::snprintf(text, sizeof text, "no lane messages on %s", lanes_channel_.c_str());
    } else {
      const LaneEstimate e = from_message(*last_lane_);
      // "-" without solved lines, "straight" beyond 10 km (noise on a straight road).
      const std::string radius = radius_text(last_lane_->radius_of_curvature_m);
      n = std::snprintf(text, sizeof text,
                        "frame %llu %s | psi %.2f theta %.2f phi %.2f deg | lane %.0f mm, offset %.0f mm, heading "
                        "%.2f deg, radius %s, departure %s, %s | %d msg/s",
                        static_cast<unsigned long long>(e.frame), e.ok ? "ok" : to_string(e.reason), e.psi_deg,
                        e.theta_deg, e.phi_deg, e.lane_width_mm, e.lateral_offset_mm, e.heading_deg, radius.c_str(),
                        to_string(e.departure), to_string(e.state), lanes_in_second_);
      const LdwEstimate& l = e.ldw;
      if (n >= 0 && static_cast<std::size_t>(n) < sizeof text) {
        // " | LDW available, warning none, DLC 910/905 mm, TLC -/1.84 s, lateral -0.05 m/s,
        // heading 0.02 deg (mount yaw -1.36)": the filter's heading, and the mount's yaw it
        // learnt, which the solve's heading above still holds.
        char tlc_left[16] = "-", tlc_right[16] = "-";
        if (l.tlc_left_s) std::snprintf(tlc_left, sizeof tlc_left, "%.2f", *l.tlc_left_s);
        if (l.tlc_right_s) std::snprintf(tlc_right, sizeof tlc_right, "%.2f", *l.tlc_right_s);
        const int m = l.available
                          ? std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n),
                                          " | LDW available, warning %s, DLC %.0f/%.0f mm, TLC %s/%s s, lateral "
                                          "%.2f m/s, heading %.2f deg (mount yaw %+.2f)",
                                          to_string(l.warning), l.dlc_left_mm, l.dlc_right_mm, tlc_left, tlc_right,
                                          l.lateral_velocity_mps, l.heading_deg, l.heading_bias_deg)
                          : std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n),
                                          " | LDW unavailable (%s)", to_string(l.reason));
        if (m > 0) n += m;
      }
    }
    if (last_status_ && n >= 0 && static_cast<std::size_t>(n) < sizeof text) {
      const status_t& s = *last_status_;
      char gyro_reconnects[48] = "";
      if (s.gyro_state != status_t::GYRO_NONE)
        std::snprintf(gyro_reconnects, sizeof gyro_reconnects, ", gyro reconnects %lld",
                      static_cast<long long>(s.gyro_reconnects_total));
      char vehicle[160];
      vehicle_words(s, vehicle, sizeof vehicle);
      std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n),
                    " | camera %s, gyro %s%s, %s, p99 %.1f ms, dropped %lld, allocations %lld",
                    camera_state_name(s.camera_state), gyro_state_name(s.gyro_state), gyro_reconnects, vehicle,
                    static_cast<double>(s.latency_p99_us) * 1e-3, static_cast<long long>(s.frames_dropped_total),
                    static_cast<long long>(s.allocations_since_ready));
      // " | calibration calibrating 45%, yaw +0.00 pitch +0.00 deg": the mount correction in use.
      if (s.calibration_state != status_t::CALIBRATION_OFF) {
        const std::size_t used = std::strlen(text);
        char progress[16] = "";
        if (s.calibration_state == status_t::CALIBRATION_CALIBRATING)
          std::snprintf(progress, sizeof progress, " %.0f%%", 100.0 * s.calibration_progress);
        std::snprintf(text + used, sizeof text - used, " | calibration %s%s, yaw %+.2f pitch %+.2f deg",
                      calibration_state_name(s.calibration_state), progress, s.calibration_yaw_deg,
                      s.calibration_pitch_deg);
      }
    }
    // Which daemon: two on one bus interleave their messages on the same channels.
    const std::string* instance = last_lane_ ? &last_lane_->instance : last_status_ ? &last_status_->instance : nullptr;
    if (instance && !instance->empty()) {
      const std::size_t used = std::strlen(text);
      std::snprintf(text + used, sizeof text - used, " | instance %s", instance->c_str());
    }
    std::cout << text << '\n';
    flush_checked(std::cout, "standard output");
    lanes_in_second_ = 0;
    lanes_printed_ = lanes_;
  }

  MonitorArgs args_;
  std::string lanes_channel_, status_channel_;
  lcm::LCM bus_;
  long long lanes_ = 0, lanes_printed_ = 0;
  int lanes_in_second_ = 0;
  std::optional<lane_estimate_t> last_lane_;
  std::optional<status_t> last_status_;
  std::exception_ptr handler_failure_;
};

}  // namespace

CommandAction setup_monitor(CLI::App& sub) {
  auto args = std::make_shared<MonitorArgs>();
  sub.add_option("--lcm", args->url, "LCM bus URL")->capture_default_str();
  sub.add_option("--prefix", args->prefix, "channel prefix ([lcm] prefix of the daemon)")->capture_default_str();
  sub.add_option("--count", args->count, "stop after N lane messages")->check(positive_number());
  sub.add_option("--seconds", args->seconds, "stop after S seconds")->check(positive_number());
  sub.add_flag("--json", args->json,
               "print each lane message as a JSON object, one per line (as ccdlane replay), and each status "
               "message as {\"status\": {...}} with the online calibration");
  sub.footer(
      "Without --json: one line a second with the latest lane estimate and the daemon's status. "
      "Exit status 1 when no lane message arrived.");
  return [args] {
    Monitor monitor(*args);
    return monitor.run();
  };
}

}  // namespace ccdlane::cli
