// What the processing thread runs on each frame: the lane estimator `ccdlane replay` runs
// too, so the daemon and replay give the same estimates for the same frames and gyro
// readings. An interface so that the pipeline's tests can run a frame checker instead.
#pragma once

#include <cstdint>
#include <optional>

#include "app/config.hpp"
#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator.hpp"
#include "daemon/online_calibration.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

class FrameProcessor {
 public:
  virtual ~FrameProcessor() = default;

  // One frame, one estimate, numbered `frame` (the pipeline's own count for the run: the
  // source's id may wrap or restart) and timed by the frame (meta.frame_t_ns()); ok =
  // false with a reason when the frame gives none. Runs on the
  // real-time path: no allocation, no exceptions; every workspace was sized when the
  // processor was built. `attitude` is the gyro reading at the frame's time (the frame's
  // own recorded reading, else the live gyro's), if there is one; `vehicle` the
  // vehicle's speed, yaw rate and indicator at it, and the devices' health.
  virtual LaneEstimate process(const ImageView& image, std::uint64_t frame, const FrameMeta& meta,
                               std::optional<Gx1Angles> attitude, const VehicleInputs& vehicle) = 0;

  // A frame the source could not deliver (ok = false, no_frame): the lane departure
  // warning coasts through it. By default, only the failed estimate.
  virtual LaneEstimate no_frame(std::uint64_t frame, const FrameMeta& meta, const VehicleInputs& /*vehicle*/) {
    LaneEstimate e;
    e.frame = frame;
    e.t_ns = meta.frame_t_ns();
    e.ok = false;
    e.reason = EstimateFailure::no_frame;
    return e;
  }
};

// The lane estimator as the daemon's processor. Gyro roll/pitch become priors inside the
// estimator ([gyro] sigma_deg, a [prior] entry overriding); yaw is never used.
class EstimatorProcessor final : public FrameProcessor {
 public:
  // Allocates the estimator's workspaces. Throws std::runtime_error when the (open)
  // source's frames are not the camera's Nu x Nv. With `calibration` (not owned; it must
  // outlive the processor) the estimator refines the mount online from where it left
  // off, and it is given the refinement's result after every frame.
  EstimatorProcessor(const Config& config, const FrameSource& source, OnlineCalibration* calibration = nullptr);

  LaneEstimate process(const ImageView& image, std::uint64_t frame, const FrameMeta& meta,
                       std::optional<Gx1Angles> attitude, const VehicleInputs& inputs) override {
    return run(
        FrameInputs{frame, meta.sequence, meta.frame_t_ns(), image, attitude, attitude_source(meta, attitude), inputs});
  }
  LaneEstimate no_frame(std::uint64_t frame, const FrameMeta& meta, const VehicleInputs& inputs) override {
    return run(
        FrameInputs{frame, meta.sequence, meta.frame_t_ns(), std::nullopt, std::nullopt, AttitudeSource::none, inputs});
  }

 private:
  LaneEstimate run(const FrameInputs& in) {
    const LaneEstimate& e = estimator_.estimate(in);
    if (calibration_) calibration_->share(estimator_.mount_refinement());
    return e;
  }

  static AttitudeSource attitude_source(const FrameMeta& meta, const std::optional<Gx1Angles>& attitude) {
    if (!attitude) return AttitudeSource::none;
    return meta.gyro ? AttitudeSource::recorded : AttitudeSource::live;
  }

  LaneEstimator estimator_;
  OnlineCalibration* calibration_ = nullptr;
};

}  // namespace ccdlane
