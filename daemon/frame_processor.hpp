// What the processing thread runs on each frame: the lane estimator `ccdlane replay` runs
// too, so the daemon and replay give the same estimates for the same frames and gyro
// readings. An interface so that the pipeline's tests can run a frame checker instead.
#pragma once

#include "app/config.hpp"
#include "core/lane/frame_inputs.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator.hpp"
#include "daemon/online_calibration.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

class FrameProcessor {
 public:
  virtual ~FrameProcessor() = default;

  // One frame, one estimate; ok = false with a reason when the frame gives none. `in` is
  // what the pipeline built once with app/frame_inputs.hpp's frame_inputs(), as replay
  // and calibrate mount build theirs: the pixels, the pipeline's own frame number for the
  // run (the source's id, which may wrap or restart, beside it), the frame's time, the
  // gyro reading at it (the frame's own recorded one, else the live gyro's) and where it
  // came from, the vehicle's speed, yaw rate and indicator and the devices' health. Runs
  // on the real-time path: no allocation, no exceptions; every workspace was sized when
  // the processor was built.
  virtual LaneEstimate process(const FrameInputs& in) = 0;

  // A frame the source could not deliver (in.image empty; ok = false, no_frame): the lane
  // departure warning coasts through it. By default, only the failed estimate.
  virtual LaneEstimate no_frame(const FrameInputs& in) {
    LaneEstimate e;
    e.frame = in.frame;
    e.t_ns = in.t_ns;
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

  LaneEstimate process(const FrameInputs& in) override { return run(in); }
  LaneEstimate no_frame(const FrameInputs& in) override { return run(in); }

 private:
  LaneEstimate run(const FrameInputs& in) {
    const LaneEstimate& e = estimator_.estimate(in);
    if (calibration_) calibration_->share(estimator_.mount_refinement());
    return e;
  }

  LaneEstimator estimator_;
  OnlineCalibration* calibration_ = nullptr;
};

}  // namespace ccdlane
