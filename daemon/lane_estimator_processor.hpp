// The daemon's FrameProcessor is the same LaneEstimator `ccdlane replay` runs, so the
// daemon and replay give the same estimates for the same frames and gyro readings.
#pragma once

#include "app/config.hpp"
#include "core/lane/lane_estimator.hpp"
#include "daemon/frame_processor.hpp"

namespace ccdlane {

class LaneEstimatorProcessor final : public FrameProcessor {
 public:
  // Allocates the estimator's workspaces for config.camera's Nu x Nv.
  explicit LaneEstimatorProcessor(const Config& config) : estimator_(config.estimator_options()) {}

  // Gyro roll/pitch become priors inside the estimator (camera_attitude_from_gx1,
  // [gyro] sigma_deg, a [prior] entry overriding); yaw is never used.
  LaneEstimate process(const ImageView& image, const FrameMeta& meta, std::optional<Gx1Angles> attitude) override {
    return estimator_.estimate(image, meta.sequence, meta.frame_t_ns(), attitude);
  }

 private:
  LaneEstimator estimator_;
};

}  // namespace ccdlane
