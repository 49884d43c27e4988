// Reading a video file (MP4, MKV, MOV, AVI with H.264, H.265 or MJPEG) frame by frame
// through FFmpeg's libraries, each frame with the time the container gives it.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "base/image_view.hpp"

namespace ccdlane {

// A file that cannot be read as a video: one line naming the file and the cause ("not a
// video", "unsupported codec", "no video stream").
class VideoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Whether `path` names a video by its extension (.mp4 .mkv .mov .avi .m4v .webm, any
// case): how the tools tell a video from an LCM log, both being single files.
bool is_video_path(std::string_view path);

enum class VideoRead : std::uint8_t {
  frame,    // `into` holds the next frame, t_ns its time
  end,      // the stream ended where its index says it ends
  damaged,  // the file is cut short or its data are damaged at this frame: problem() says which
};

class VideoReader {
 public:
  // Opens the file and its first video stream, ready to decode. Throws VideoError.
  explicit VideoReader(std::string path);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  const std::string& path() const { return path_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // mono8 for a grey video, else rgb8: colour is kept, as a colour camera delivers it.
  PixelFormat format() const { return format_; }
  const std::string& codec() const { return codec_; }               // "h264", "hevc", "mjpeg"
  double frame_rate_hz() const { return rate_hz_; }                 // the container's average; 0 when unknown
  std::int64_t frames_in_index() const { return indexed_frames_; }  // 0 when the container does not say
  // The stream's time base (seconds per tick), so that a writer can keep the times exactly.
  int time_base_num() const { return tb_num_; }
  int time_base_den() const { return tb_den_; }

  // Decodes the next frame into `into` (width() x height() of format()). t_ns is the frame's
  // presentation time from the container, 0 at the first frame. A frame whose time does not
  // increase is skipped and counted (non_monotonic()). After `damaged` or `end`, next()
  // returns the same until rewind(). Allocates only inside FFmpeg (its own malloc).
  VideoRead next(const MutableImageView& into, std::int64_t& t_ns);

  // Back to the first frame (loop playback). Returns false when the file cannot seek.
  bool rewind();

  std::uint64_t frames_read() const { return frames_read_; }
  // The last frame next() delivered, counted as the file holds them (skipped ones included).
  std::uint64_t frame_index() const { return decoded_ > 0 ? decoded_ - 1 : 0; }
  std::uint64_t non_monotonic() const { return non_monotonic_; }
  // The first frame (0-based, counting skipped ones) whose time did not increase; -1 if none.
  std::int64_t first_non_monotonic() const { return first_non_monotonic_; }
  // After `damaged`: "<path>: frame N: <what is wrong>" (a fixed buffer, no allocation).
  std::string_view problem() const { return problem_.data(); }

 private:
  struct Codec;
  VideoRead fail(const char* what, int av_error);
  int receive(std::int64_t& pts);
  bool convert(const MutableImageView& into);

  std::string path_;
  std::unique_ptr<Codec> av_;
  int width_ = 0, height_ = 0;
  PixelFormat format_ = PixelFormat::rgb8;
  std::string codec_;
  double rate_hz_ = 0.0;
  std::int64_t indexed_frames_ = 0;
  int tb_num_ = 1, tb_den_ = 1;
  std::uint64_t frames_read_ = 0;  // delivered since open or rewind
  std::uint64_t decoded_ = 0;      // decoded since open or rewind, skipped ones included
  std::uint64_t non_monotonic_ = 0;
  std::int64_t first_non_monotonic_ = -1;
  std::int64_t origin_pts_ = 0;
  std::int64_t last_pts_ = 0;
  bool have_origin_ = false;
  bool draining_ = false;
  VideoRead stopped_ = VideoRead::frame;  // `frame` while reading goes on
  std::array<char, 512> problem_{};
};

}  // namespace ccdlane
