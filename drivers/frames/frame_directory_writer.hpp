// Writing a frame directory (used by `ccdlane synth` and `ccdlane grab --out`): one picture
// per frame and a frames.csv row each, with nothing partial left behind on failure.
#pragma once

#include <cstdint>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "base/turn_indicator.hpp"
#include "drivers/frames/frame_directory_error.hpp"

namespace ccdlane {

struct FrameDirectoryLayout {
  bool gyro = false;                       // write roll_deg,pitch_deg,yaw_deg columns
  std::vector<std::string> truth_columns;  // each must start with "truth_"
  bool vehicle = false;                    // write speed_kmh,turn_indicator columns
};

// The vehicle at a frame, as frames.csv's speed_kmh and turn_indicator columns hold it.
struct FrameVehicle {
  std::optional<double> speed_kmh;  // empty: an empty cell (replay then uses [vehicle] speed_kmh)
  TurnIndicator indicator = TurnIndicator::none;
};

// Each image is written under a temporary name and renamed into place, so an image file
// is either whole or absent. Rows go to a new frames.csv.tmp.XXXXXX as they come
// (flushed each frame) and finish() renames it to frames.csv: a directory without
// frames.csv is an unfinished recording. A writer destroyed without finish() (an error, an exception) removes the
// files it wrote, and the directory if it created it. Errors throw FrameDirectoryError
// naming the file and the reason.
class FrameDirectoryWriter {
 public:
  // Creates `dir` (and parents) if needed. Refuses a directory that already holds a
  // frames.csv, so an earlier recording is never overwritten, or any name a recording
  // writes (frames.csv.tmp, NNNNNN.pgm/.png), so a user's file is never replaced.
  FrameDirectoryWriter(std::string dir, FrameDirectoryLayout layout);
  ~FrameDirectoryWriter();
  FrameDirectoryWriter(const FrameDirectoryWriter&) = delete;
  FrameDirectoryWriter& operator=(const FrameDirectoryWriter&) = delete;

  // Writes frame number frames_written(): grey frames as "%06d.pgm" (PGM: 16-bit depth
  // kept, no compression to cost time), colour frames as "%06d.png" (PNG, zlib level 1:
  // about 40 % of the PPM's bytes on road pictures, ~30 ms of one core per 1280x720
  // frame, tests/bench/frame_io_bench). `gyro` empty = no reading for this frame (empty
  // cells); `truth` has one value per truth column (NaN = empty cell); `vehicle` goes to
  // the vehicle columns when the layout has them.
  void write(const ImageView& image, std::int64_t t_ns, const std::optional<Gx1Angles>& gyro = std::nullopt,
             std::span<const double> truth = {}, const FrameVehicle& vehicle = {});

  // Puts frames.csv in place. After this the destructor leaves everything where it is.
  void finish();
  // After a failed write (a full disk): frames.csv with the rows of the frames written
  // whole, put in place, so a long recording keeps what it had. Returns "" or why not.
  std::string keep_written() noexcept;

  std::size_t frames_written() const { return files_.size(); }
  std::size_t frames_kept() const { return kept_frames_; }
  const std::string& path() const { return dir_; }

 private:
  void abandon() noexcept;

  std::string dir_;
  FrameDirectoryLayout layout_;
  std::string tmp_csv_;
  std::ofstream csv_;
  std::vector<std::string> files_;  // written so far, removed if never finished
  bool created_dir_ = false;
  bool finished_ = false;
  std::int64_t last_t_ns_ = 0;
  std::size_t kept_frames_ = 0;   // frames whose row reached frames.csv.tmp
  std::streamoff csv_bytes_ = 0;  // of frames.csv.tmp up to the last whole row
};

}  // namespace ccdlane
