// A video file as a tool's recording (replay, score, calibrate mount, record): opened with
// its frame size checked against the camera's, read to the end, its problems said in one
// line each.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "app/config.hpp"
#include "drivers/frames/video_reader.hpp"

namespace ccdlane::cli {

// Whether a tool's recording argument is a video file (rather than a frame directory or
// an LCM log): a regular file with a video's extension.
bool is_video_recording(const std::string& path);

// Opens the video; UsageError (exit 2) naming the file and the cause, or the frame size
// against the camera's of `config_path`.
std::unique_ptr<VideoReader> open_video_recording(const std::string& path, const Config& config,
                                                  const std::string& config_path);

// Every frame to `frame` (image, frame number in the file, time in ns from the first).
// Returns "" when the whole file was read, else the one line that says what stopped it or
// what was wrong: damage or a cut (naming the frame and how many came before it), frames
// whose time did not increase (counted, the first named, skipped).
std::string read_video_recording(VideoReader& video,
                                 const std::function<void(const ImageView&, std::uint64_t, std::int64_t)>& frame);

}  // namespace ccdlane::cli
