// Video recordings for the tools: the checks and messages every subcommand shares.
#include "tools/ccdlane/video_recording.hpp"

#include <filesystem>

#include "base/image_buffer.hpp"
#include "tools/ccdlane/command.hpp"

namespace ccdlane::cli {

bool is_video_recording(const std::string& path) {
  std::error_code ec;
  return is_video_path(path) && !std::filesystem::is_directory(path, ec);
}

std::unique_ptr<VideoReader> open_video_recording(const std::string& path, const Config& config,
                                                  const std::string& config_path) {
  std::unique_ptr<VideoReader> video;
  try {
    video = std::make_unique<VideoReader>(path);
  } catch (const VideoError& e) {
    throw UsageError(e.what());
  }
  const int W = config.camera.Nu, H = config.camera.Nv;
  if (video->width() != W || video->height() != H)
    throw UsageError(path + ": frames are " + std::to_string(video->width()) + "x" + std::to_string(video->height()) +
                     ", the camera of " + config_path + " is " + std::to_string(W) + "x" + std::to_string(H));
  return video;
}

std::string read_video_recording(VideoReader& video,
                                 const std::function<void(const ImageView&, std::uint64_t, std::int64_t)>& frame) {
  const ImageBuffer buffer(video.width(), video.height(), video.format(), 8);
  std::int64_t t_ns = 0;
  VideoRead got;
  while ((got = video.next(buffer.view(), t_ns)) == VideoRead::frame) frame(buffer.view(), video.frame_index(), t_ns);
  if (got == VideoRead::damaged)
    return std::string(video.problem()) + "; the " + std::to_string(video.frames_read()) +
           " frames before it were processed";
  if (video.non_monotonic() > 0)
    return video.path() + ": " + std::to_string(video.non_monotonic()) +
           " frame(s) whose time does not come after the one before, skipped (the first: frame " +
           std::to_string(video.first_non_monotonic()) + ")";
  return "";
}

}  // namespace ccdlane::cli
