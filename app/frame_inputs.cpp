// The daemon's rules for a frame's inputs, in one place, so that replay judges a
// recorded frame as ccdlaned judged it live.
#include "app/frame_inputs.hpp"

namespace ccdlane {

FrameMeta recorded_frame_meta(const FrameRow& row) {
  FrameMeta meta;
  meta.sequence = row.index;
  meta.t_ns = row.t_ns;
  meta.gyro = row.gyro;
  meta.speed_kmh = row.speed_kmh;
  meta.indicator = row.indicator;
  return meta;
}

FrameMeta recorded_frame_meta(const FrameRecord& record) {
  FrameMeta meta;
  meta.sequence = record.sequence;
  meta.t_ns = record.t_ns;
  meta.gyro = record.gyro;
  meta.speed_kmh = record.speed_kmh;
  meta.yaw_rate_radps = record.yaw_rate_radps;
  meta.indicator = record.indicator;
  return meta;
}

FrameInputs frame_inputs(const ImageView* image, std::uint64_t frame, const FrameMeta& meta, const LiveReadings& live,
                         bool gyro_configured) {
  FrameInputs in;
  in.frame = frame;
  in.source_frame = meta.sequence;
  in.t_ns = meta.frame_t_ns();
  if (image) in.image = *image;
  if (meta.gyro) {
    in.gyro = meta.gyro;
    in.attitude_source = AttitudeSource::recorded;
  } else if (image && live.gyro) {
    in.gyro = live.gyro;
    in.attitude_source = AttitudeSource::live;
  }
  VehicleInputs& v = in.vehicle;
  if (meta.speed_kmh || meta.indicator || meta.yaw_rate_radps) {
    if (meta.speed_kmh) v.speed_mps = *meta.speed_kmh / 3.6;
    v.yaw_rate_radps = meta.yaw_rate_radps;
    v.indicator = meta.indicator.value_or(TurnIndicator::none);
  } else if (live.vehicle) {
    v = *live.vehicle;
  }
  v.camera_ok = image != nullptr;
  v.gyro_ok = image ? !gyro_configured || in.gyro.has_value() : live.gyro_delivering;
  if (image && !v.yaw_rate_radps && !meta.gyro) v.yaw_rate_radps = live.yaw_rate_radps;
  return in;
}

}  // namespace ccdlane
