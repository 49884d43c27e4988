// Writing a video file (H.264 in MP4 by default) frame by frame through FFmpeg's
// libraries, each frame at a given time: annotated replays and test recordings.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "base/image_view.hpp"

namespace ccdlane {

struct VideoWriterOptions {
  int width = 0;
  int height = 0;
  // "libx264" (H.264), "libx265" (H.265) or "mjpeg"; the container follows the file's
  // extension (.mp4, .mkv, .mov, .avi).
  std::string encoder = "libx264";
  bool lossless = false;  // H.264/H.265 at qp 0 (up to the RGB -> YUV rounding)
  // Time base of the frame times (seconds per tick): a replay writes in its input's, so
  // that its frames keep their times exactly. 1/90000 s unless told.
  int time_base_num = 1;
  int time_base_den = 90'000;
};

class VideoWriter {
 public:
  // Creates `path` as a temporary file (`path.part`) that finish() renames: a failed or
  // interrupted run leaves no half file under the name asked for. Throws
  // std::runtime_error naming the file and the cause.
  VideoWriter(std::string path, VideoWriterOptions options);
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // One frame (width x height, mono8, rgb8 or bgr8) at t_ns (increasing). Throws on failure.
  void write(const ImageView& frame, std::int64_t t_ns);
  // Flushes the encoder, writes the index and renames the file into place.
  void finish();
  std::uint64_t frames() const { return frames_; }
  const std::string& path() const { return path_; }

 private:
  struct Codec;
  void drain(bool flushing);

  std::string path_;
  std::string part_path_;
  VideoWriterOptions options_;
  std::unique_ptr<Codec> av_;
  std::uint64_t frames_ = 0;
  std::int64_t last_pts_ = -1;
  std::int64_t last_interval_ = 1;  // between the last two frames, in the time base
  bool finished_ = false;
};

}  // namespace ccdlane
