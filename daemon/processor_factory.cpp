// Until the lane estimator is wired in, frames go to the test-pattern checker.
#include "daemon/processor_factory.hpp"

#include "daemon/test_pattern.hpp"

namespace ccdlane {

std::unique_ptr<FrameProcessor> make_frame_processor(const Config&, const FrameSource&) {
  return std::make_unique<TestPatternProcessor>();
}

}  // namespace ccdlane
