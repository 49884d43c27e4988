// LCM log files of raw frames (lcm::LogFile, no network): written by `ccdlane record
// ... --out FILE.lcmlog`, read by `ccdlane replay CONFIG FILE.lcmlog`. The same files
// lcm-logger writes from a ccdlaned with [lcm] publish_frames = true.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <ccdlane/frame_t.hpp>

#include "base/unique_fd.hpp"
#include "bus/frame_message.hpp"
#include "bus/lcm_log_scanner.hpp"

namespace lcm {
class LogFile;
}

namespace ccdlane {

// A log that cannot be used at all: not readable, not writable, already there. The
// message names the file and the reason.
class FrameLogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes frame_t events on one channel. The log is written under a temporary name (a
// new PATH.tmp.XXXXXX, base/temp_file.hpp) and renamed into place by finish(); a writer
// destroyed without finish() (an error, an interrupted run) removes it, so a log is
// either whole or absent.
class FrameLogWriter {
 public:
  // Refuses a path that exists, so an earlier recording is never overwritten.
  FrameLogWriter(std::string path, std::string channel);
  ~FrameLogWriter();
  FrameLogWriter(const FrameLogWriter&) = delete;
  FrameLogWriter& operator=(const FrameLogWriter&) = delete;

  // The event's timestamp is record.utime. Throws FrameLogError when the disk refuses.
  void write(const ImageView& image, const FrameRecord& record);
  void finish();
  // After a failed write (a full disk): cuts the file back to the last whole event and
  // renames it into place, so a long recording keeps what it had. Returns "" or why the
  // frames could not be kept (the .tmp file then stays, for the reader to salvage).
  std::string keep_written() noexcept;

  std::size_t frames_written() const { return frames_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_, channel_;
  std::unique_ptr<lcm::LogFile> log_;
  frame_t message_{};
  std::vector<std::uint8_t> bytes_;
  std::size_t frames_ = 0;
  long long whole_bytes_ = 0;  // the file up to the end of the last event written and flushed
  bool finished_ = false;
};

// Reads the frame_t events of one channel in log order; events of other channels (lane
// and status messages in a log of ccdlaned's bus) are counted and passed over. The
// framing is checked here (LcmLogScanner), not by liblcm: damaged stretches of the file
// are skipped to the next valid event and reported as `lost`.
class FrameLogReader {
 public:
  // Throws FrameLogError when the file cannot be opened.
  FrameLogReader(std::string path, std::string channel);
  ~FrameLogReader();
  FrameLogReader(const FrameLogReader&) = delete;
  FrameLogReader& operator=(const FrameLogReader&) = delete;

  enum class Next : std::uint8_t {
    frame,    // image() and record() hold the next frame
    damaged,  // a frame_t event that does not decode or holds no usable image: problem()
              // says which (the 0-based event of the file) and why; record() has what
              // could be read (the sequence, when it decoded)
    lost,     // a damaged stretch of the file was skipped, or the file ends inside an
              // event: problem() says where and how many bytes; lost_events() grew
    end,
  };
  Next next();

  const ImageView& image() const { return image_; }
  const FrameRecord& record() const { return record_; }
  const std::string& problem() const { return problem_; }
  std::size_t frames() const { return frames_; }              // frame events read, damaged or not
  std::size_t other_events() const { return other_events_; }  // on other channels
  // Events of any channel lost to damage or to a cut end (LcmLogScanner::events_lost).
  std::uint64_t lost_events() const { return scanner_->events_lost(); }
  std::uint64_t lost_bytes() const { return scanner_->bytes_skipped(); }
  bool truncated() const { return scanner_->truncated_tail(); }
  const std::string& path() const { return path_; }
  const std::string& channel() const { return channel_; }

 private:
  std::string path_, channel_;
  UniqueFd fd_;
  std::unique_ptr<LcmLogScanner> scanner_;
  std::uint64_t regions_reported_ = 0;
  bool pending_event_ = false, tail_reported_ = false;
  frame_t message_{};
  ImageView image_;
  FrameRecord record_;
  std::string problem_;
  std::size_t events_ = 0, frames_ = 0, other_events_ = 0;
};

}  // namespace ccdlane
