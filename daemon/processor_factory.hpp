// The FrameProcessor the processing thread runs for a configuration.
#pragma once

#include <memory>

#include "app/config.hpp"
#include "daemon/frame_processor.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

// Built for the (open) source's frame size; allocates every workspace now.
std::unique_ptr<FrameProcessor> make_frame_processor(const Config& config, const FrameSource& source);

}  // namespace ccdlane
