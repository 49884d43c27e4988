// [source] kind -> the FrameSource that captures it.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "app/config.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

// Whether the frames of [source] come with their own gyro reading: "" when they do
// (synthetic frames carry their drive's; a frame directory whose frames.csv has the
// roll_deg and pitch_deg columns, read now, its recorded one), else the cause in one
// line, naming the file for a frame directory. A directory that cannot be read counts
// as carrying them: opening it says what is wrong.
std::string frames_without_gyro(const Config& config);

// The source for [source], not yet opened. Throws std::runtime_error when a camera
// string cannot be made into a source.
// `cancelled`, when given, is asked during long start-up work (rendering the synthetic
// drive), which then gives up so that open() returns at once.
std::unique_ptr<FrameSource> make_frame_source(const Config& config, std::function<bool()> cancelled = {});

}  // namespace ccdlane
