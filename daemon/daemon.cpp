// The main thread is the status thread: it waits for signals with a timeout that is the
// next status tick, so shutdown and reporting need no extra thread and no handler.
#include "daemon/daemon.hpp"

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <optional>

#include "app/gyro_factory.hpp"
#include "app/source_factory.hpp"
#include "app/synth_source.hpp"
#include "base/clock.hpp"
#include "base/log.hpp"
#include "bus/channels.hpp"
#include "bus/lcm_publisher.hpp"
#include "bus/vehicle_state_listener.hpp"
#include "core/lane/observability.hpp"
#include "daemon/allocation_counter.hpp"
#include "daemon/bus_thread.hpp"
#include "daemon/frame_processor.hpp"
#include "daemon/latency_window.hpp"
#include "daemon/memory_estimate.hpp"
#include "daemon/online_calibration.hpp"
#include "daemon/pipeline.hpp"
#include "daemon/realtime.hpp"
#include "daemon/sd_notifier.hpp"
#include "daemon/service_heartbeat.hpp"
#include "daemon/signal_waiter.hpp"
#include "daemon/status_report.hpp"

namespace ccdlane {
namespace {

constexpr std::int64_t kStatusPeriodNs = 1'000'000'000;
// With the unit's RestartSec=2s: a start attempt every 7 s while the camera is away.
constexpr std::int64_t kRestartPauseNs = 5'000'000'000;

// Everything the status thread reads once a second, gathered without allocating.
class StatusTicker {
 public:
  StatusTicker(Pipeline& pipeline, AttitudeProvider* gyro, OnlineCalibration& calibration, LcmPublisher& publisher,
               SystemdNotifier& notifier, const std::string& camera, std::int64_t start_ns)
      : pipeline_(pipeline),
        gyro_(gyro),
        calibration_(calibration),
        publisher_(publisher),
        notifier_(notifier),
        report_(camera, publisher.instance()),
        window_(1 << 16),
        start_ns_(start_ns) {}

  void tick() {
    if (const char* other = publisher_.take_other_instance())
      log_line(LogLevel::warning, "lcm",
               "another publisher on %s: instance \"%s\" (we are \"%s\"); its messages interleave with ours on %s "
               "(said once)",
               publisher_.status_channel().c_str(), other, publisher_.instance().c_str(), publisher_.url().c_str());
    pipeline_.drain_latency(window_);
    char camera_problem[kStatusTextMax + 1];
    char gyro_problem[kStatusTextMax + 1] = "";
    pipeline_.camera_problem(camera_problem, sizeof camera_problem);
    StatusInputs in;
    in.utime = realtime_us();
    in.uptime_us = (monotonic_ns() - start_ns_) / 1000;
    in.totals = pipeline_.totals();
    in.latency = window_.take();
    in.camera_problem = camera_problem;
    if (gyro_) {
      in.gyro = gyro_->state();
      in.gyro_counters = gyro_->counters();
      gyro_->last_problem(gyro_problem, sizeof gyro_problem);
    }
    in.gyro_problem = gyro_problem;
    if (vehicle_) in.vehicle = vehicle_->counters(monotonic_ns(), kVehicleStateMaxAgeNs);
    in.allocations_since_ready = in.totals.ready ? allocation_counter::count() : 0;
    calibration_.tick(monotonic_ns());
    in.calibration = calibration_.status();
    report_.update(in);
    if (!publisher_.publish_status(report_.message()) && first_time(said_publish_failed_))
      log_line(LogLevel::warning, "lcm", "%s: publishing status on %s failed (further failures not logged)",
               publisher_.url().c_str(), publisher_.status_channel().c_str());
    char line[256];
    report_.summary_line(line, sizeof line);
    notifier_.status(line);
  }

  const status_t& last() const { return report_.message(); }
  // The vehicle gateway's state and refusals go into status; null: none shown.
  void watch_vehicle(const VehicleStateListener* vehicle) { vehicle_ = vehicle; }

 private:
  Pipeline& pipeline_;
  AttitudeProvider* gyro_;
  OnlineCalibration& calibration_;
  LcmPublisher& publisher_;
  SystemdNotifier& notifier_;
  StatusReport report_;
  LatencyWindow window_;
  std::int64_t start_ns_;
  std::atomic<bool> said_publish_failed_{false};
  const VehicleStateListener* vehicle_ = nullptr;
};

// A failed start under systemd: the reason in STATUS= (what `systemctl status` shows
// while the unit restarts, StartLimitIntervalSec=0 letting it restart for ever), then a
// pause that spaces the restarts out while a camera stays away. SIGTERM ends the pause.
// Run by hand (no NOTIFY_SOCKET), it exits at once.
void pause_before_restart(SystemdNotifier& notifier, SignalWaiter& signals, const char* category, const char* why) {
  if (!notifier.enabled()) return;
  char line[400];
  std::snprintf(line, sizeof line, "failed to start (%s): %.300s; restarting in %d s", category, why,
                static_cast<int>(kRestartPauseNs / 1'000'000'000));
  notifier.status(line);
  for (const std::int64_t until = monotonic_ns() + kRestartPauseNs; monotonic_ns() < until;)
    if (signals.wait(until - monotonic_ns()) == SignalWaiter::Event::terminate) return;
}

// "host:pid": which daemon sent a message, when two share a bus.
std::string instance_name() {
  char host[256] = "";
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "unknown-host");
  return std::string(host) + ":" + std::to_string(getpid());
}

}  // namespace

std::string solver_observability_problem(const Config& c) {
  // Synthetic frames carry their drive's gyro reading and frame directories (most) their
  // recorded one: the roll is measured when either they or the [gyro] device give it.
  const std::string no_recorded_gyro = c.gyro.device.empty() ? frames_without_gyro(c) : "";
  const Observability o = observability(c.estimator_options(), no_recorded_gyro.empty());
  // A frame directory is expected to carry its gyro: name the file that does not.
  if (o == Observability::roll_unobservable && !no_recorded_gyro.empty() && c.source.kind == SourceKind::frames)
    return no_recorded_gyro +
           " and there is no [gyro] device, no [prior] phi_deg and no [prior] lane_width_mm, "
           "while solver.free has phi and y0: the roll is not observable; add one of them or fix phi";
  return explain(o);
}

std::string daemon_config_problem(const Config& config) {
  if (std::string why = solver_observability_problem(config); !why.empty()) return why;
  return memory_problem(config, available_memory_bytes());
}

Config demo_config() {
  Config c = default_config();
  c.source.kind = SourceKind::synth;
  c.source.rate_hz = 30.0;
  // Six seconds of drive, looped: one weave across the lane in its own 6 s (a shorter
  // loop would make it a faster weave, as a drifting car's), whole bump and sway cycles.
  c.synth.frames = static_cast<int>(SynthSourceOptions::kMaxSeconds * c.synth.rate_hz);
  c.gyro.device = "emulated";
  return c;
}

namespace {

// What ccdlaned runs on, made and opened by start_up() in this order.
struct Devices {
  std::unique_ptr<FrameSource> source;
  std::unique_ptr<AttitudeProvider> gyro;
  std::unique_ptr<OnlineCalibration> calibration;  // before the processor, which it outlives
  std::unique_ptr<EstimatorProcessor> processor;
  std::unique_ptr<LcmPublisher> publisher;
  std::unique_ptr<VehicleStateListener> vehicle;
  bool source_open = false, gyro_open = false;
  SystemdNotifier* notifier = nullptr;  // for the pause before a restart
  SignalWaiter* signals = nullptr;

  // A start that fails half-way leaves no stream running and no device open.
  int fail(const char* category, const char* why) {
    log_line(LogLevel::error, category, "%s", why);
    if (gyro_open) gyro->close();
    if (source_open) source->close();
    if (notifier && signals) pause_before_restart(*notifier, *signals, category, why);
    return 1;
  }
};

// A SIGTERM while a device took its time to open (seconds of handshakes) ends the start.
bool terminated_during_start_up(SignalWaiter& signals) {
  if (!signals.terminate_pending() || signals.wait(0) != SignalWaiter::Event::terminate) return false;
  log_line(LogLevel::info, "stop", "SIG%s during start-up: stopping", sigabbrev_np(signals.last_signal()));
  return true;
}

// Opens the source and the gyro; the exit status when the daemon is not to go on.
std::optional<int> open_devices(const Config& config, SignalWaiter& signals, Devices& d) {
  // Rendering the synthetic drive takes seconds: a SIGTERM meanwhile must not wait for it.
  d.source = make_frame_source(config, [&signals] { return signals.terminate_pending(); });
  if (std::string why = d.source->open(); !why.empty())
    return terminated_during_start_up(signals) ? 0 : d.fail("camera", why.c_str());
  d.source_open = true;
  // A sensor that does not answer takes seconds of handshakes: SIGTERM ends them.
  d.gyro = make_attitude_provider(config, {}, [&signals] { return signals.terminate_pending(); });
  if (!d.gyro) return std::nullopt;
  // An absent gyro degrades the estimate, it does not stop the lanes: a gyro lost
  // mid-run is handled so too, and a daemon that exits here is restart-looped.
  if (std::string why = d.gyro->open(); !why.empty()) {
    if (terminated_during_start_up(signals)) {
      d.source->close();
      return 0;
    }
    if (d.gyro->state() != GyroState::lost) return d.fail("gyro", why.c_str());
    log_line(LogLevel::warning, "gyro", "absent: %s; running without it and retrying the device", why.c_str());
  }
  d.gyro_open = true;
  return std::nullopt;
}

// The online calibration, the processor and the bus.
void make_processing(const Config& config, Devices& d) {
  d.calibration = std::make_unique<OnlineCalibration>(config);  // the estimator starts from its state file
  d.processor =
      std::make_unique<EstimatorProcessor>(config, *d.source, d.calibration->enabled() ? d.calibration.get() : nullptr);
  d.publisher = std::make_unique<LcmPublisher>(config.lcm);
  d.publisher->set_instance(config.lcm.instance.empty() ? instance_name() : config.lcm.instance);
  d.publisher->watch_for_other_instances();
  d.vehicle = std::make_unique<VehicleStateListener>(d.publisher->bus().getUnderlyingLCM(),
                                                     channel_name(config.lcm.prefix, Channel::vehicle));
  // [lcm] publish_frames: raw frames on their own channel, so lcm-logger records a drive.
  if (config.lcm.publish_frames) d.publisher->enable_frames(d.source->width(), d.source->height(), d.source->format());
}

void log_started(const Config& config, const Devices& d, const Pipeline& pipeline, const SystemdNotifier& notifier) {
  const FramePoolLayout& pool = pipeline.pool().layout();
  log_line(LogLevel::info, "start",
           "%s; gyro %s; %d frame buffers of %dx%d; lanes on %s, status on %s, vehicle state from %s, bus %s, "
           "instance %s",
           d.source->describe().c_str(), d.gyro ? d.gyro->describe().c_str() : "none", pool.count, pool.width,
           pool.height, d.publisher->lanes_channel().c_str(), d.publisher->status_channel().c_str(),
           channel_name(config.lcm.prefix, Channel::vehicle).c_str(), d.publisher->url().c_str(),
           d.publisher->instance().c_str());
  if (notifier.watchdog_interval_us() > 0)
    log_line(LogLevel::info, "systemd", "watchdog every %.3f s, pinged while frames flow",
             static_cast<double>(notifier.watchdog_interval_us()) * 1e-6);
}

// Until SIGTERM or the end of a finite source. The main thread allocates nothing here:
// it waits, counts, tells systemd and publishes status.
void serve(SignalWaiter& signals, const Pipeline& pipeline, ServiceHeartbeat& heartbeat, StatusTicker& status) {
  std::int64_t next_status = monotonic_ns() + kStatusPeriodNs;
  for (;;) {
    const std::int64_t now = monotonic_ns();
    const std::int64_t wait = std::min(next_status - now, heartbeat.tick_period_ns());
    const SignalWaiter::Event event = signals.wait(wait);
    if (event == SignalWaiter::Event::terminate) {
      log_line(LogLevel::info, "stop", "SIG%s: stopping", sigabbrev_np(signals.last_signal()));
      return;
    }
    if (event == SignalWaiter::Event::hangup) {
      log_line(LogLevel::notice, "config",
               "SIGHUP: reloading the configuration is not supported; restart ccdlaned to apply changes");
      continue;
    }
    const PipelineTotals totals = pipeline.totals();
    heartbeat.tick(monotonic_ns(), totals.ready, totals.frames_processed);
    if (pipeline.finished()) {
      log_line(LogLevel::info, "stop", "the source ended and every frame was processed: stopping");
      return;
    }
    if (monotonic_ns() >= next_status) {
      status.tick();
      next_status += kStatusPeriodNs;
      if (next_status < monotonic_ns()) next_status = monotonic_ns() + kStatusPeriodNs;
    }
  }
}

void log_stopped(const StatusTicker& status, const Pipeline& pipeline) {
  const status_t& s = status.last();
  // in = processed + dropped + left queued at the stop: every frame is accounted for.
  log_line(LogLevel::info, "stop",
           "%lld frames in, %lld processed, %lld dropped, %lld left queued at stop, %lld not ok, "
           "%lld allocations after ready",
           static_cast<long long>(s.frames_in_total), static_cast<long long>(s.frames_processed_total),
           static_cast<long long>(s.frames_dropped_total), static_cast<long long>(pipeline.totals().frames_unprocessed),
           static_cast<long long>(s.frames_not_ok_total), static_cast<long long>(s.allocations_since_ready));
}

}  // namespace

int run_daemon(const Config& config) {
  const std::int64_t start_ns = monotonic_ns();
  SignalWaiter signals;  // before any thread exists, so that all of them inherit the mask
  SystemdNotifier notifier;
  RealtimeSetup realtime(config.realtime);
  Devices d;
  d.notifier = &notifier;
  d.signals = &signals;
  try {
    if (const std::optional<int> status = open_devices(config, signals, d)) return *status;
    make_processing(config, d);
  } catch (const std::exception& e) {
    return d.fail("start", e.what());
  }

  Pipeline pipeline(*d.source, d.gyro.get(), *d.processor, *d.publisher, realtime, pipeline_options(config));
  pipeline.set_vehicle_state(d.vehicle.get(), kVehicleStateMaxAgeNs);
  // The one thread that handles the bus: vehicle states as they come, other instances.
  BusThread bus(d.publisher->bus().getUnderlyingLCM());
  ServiceHeartbeat heartbeat(notifier);
  StatusTicker status(pipeline, d.gyro.get(), *d.calibration, *d.publisher, notifier, d.source->describe(), start_ns);
  status.watch_vehicle(d.vehicle.get());
  log_started(config, d, pipeline, notifier);

  pipeline.start();
  bus.start();
  realtime.lock_memory();
  char rt[160];
  realtime.describe(rt, sizeof rt);
  log_line(LogLevel::info, "realtime", "%s", rt);
  pipeline.run();
  serve(signals, pipeline, heartbeat, status);

  notifier.stopping();
  pipeline.stop();  // threads joined: the capture wait is bounded, queued frames are left
  bus.stop();
  d.source->close();  // streams off, device closed
  if (d.gyro) d.gyro->close();
  d.calibration->stop();  // the processing thread has ended: the last estimate is saved
  status.tick();          // the last word on the bus; udpm sends synchronously, nothing is left queued
  log_stopped(status, pipeline);
  return 0;
}

}  // namespace ccdlane
