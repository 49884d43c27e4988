// [gyro] device: "" = no gyro, "emulated" = the 3DM-GX1 emulator on a pty in this
// process (following the synthetic drive's attitude), anything else = a serial device.
#include "app/gyro_factory.hpp"

#include <cmath>
#include <memory>

#include "app/gx1_attitude_provider.hpp"
#include "app/synth_source.hpp"
#include "base/log.hpp"
#include "core/synth/synth_drive.hpp"

namespace ccdlane {
namespace {

// The attitude the synth source's frames show at t_s seconds of playback (the source
// loops over its rendered frames, so does this). The emulator starts just after the
// source has rendered its frames, so the two clocks agree to within the gyro's
// start-up time (tens of ms, against sway and bump periods of seconds).
gx1::AttitudeScript follow_synth_drive(const Config& config) {
  auto drive = std::make_shared<SynthDrive>(synth_source_drive(config));
  const double rate = config.source.rate_hz > 0 ? config.source.rate_hz : config.synth.rate_hz;
  const auto count = static_cast<std::uint64_t>(synth_source_frame_count(config));
  return [drive, rate, count](double t_s) {
    const auto k = static_cast<std::uint64_t>(std::max(0.0, std::floor(t_s * rate)));
    return drive->frame(k % count).gyro;
  };
}

}  // namespace

std::unique_ptr<AttitudeProvider> make_attitude_provider(const Config& config, const LogSink& log,
                                                         std::function<bool()> open_cancelled) {
  if (config.gyro.device.empty()) return nullptr;
  // 0x31: the angles and the angular rate, whose yaw rate drives the lane filter between
  // frames when no vehicle_state_t yaw rate arrives (23 bytes a reply: 160 Hz at 38400 baud).
  gx1::SessionOptions session;
  session.stream_command = gx1::cmd::stab_euler_vectors;
  std::unique_ptr<Gx1AttitudeProvider> provider;
  if (config.gyro.device == "emulated") {
    gx1::EmulatorOptions o;
    o.attitude = follow_synth_drive(config);
    provider = std::make_unique<Gx1AttitudeProvider>(std::move(o), log, session);
  } else {
    provider = std::make_unique<Gx1AttitudeProvider>(config.gyro.device, log, session);
  }
  provider->set_open_cancelled(std::move(open_cancelled));
  return provider;
}

}  // namespace ccdlane
