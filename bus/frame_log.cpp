// Frame logs through lcm::LogFile, with a temporary name until the recording is finished.
#include "bus/frame_log.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <lcm/lcm-cpp.hpp>

#include "base/temp_file.hpp"

namespace ccdlane {
namespace {

// Every event of an LCM log starts with this sync word, big-endian (lcm/eventlog.c).
constexpr unsigned char kLcmLogSync[4] = {0xED, 0xA1, 0xDA, 0x01};

bool starts_with_lcm_event(const std::string& path) {
  unsigned char head[4] = {};
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  const std::size_t n = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  return n == sizeof head && std::memcmp(head, kLcmLogSync, sizeof head) == 0;
}

}  // namespace

FrameLogWriter::FrameLogWriter(std::string path, std::string channel)
    : path_(std::move(path)), channel_(std::move(channel)) {
  struct stat st {};
  if (::lstat(path_.c_str(), &st) == 0) throw FrameLogError(path_ + ": already exists; choose another name");
  tmp_ = new_temp_beside(path_);
  if (tmp_.empty()) throw FrameLogError(path_ + ": cannot create a temporary beside it: " + std::strerror(errno));
  log_ = std::make_unique<lcm::LogFile>(tmp_, "w");
  if (!log_->good()) {
    const int error = errno;
    log_.reset();
    ::unlink(tmp_.c_str());
    throw FrameLogError(tmp_ + ": cannot create: " + std::strerror(error));
  }
}

FrameLogWriter::~FrameLogWriter() {
  if (finished_) return;
  log_.reset();
  ::unlink(tmp_.c_str());
}

void FrameLogWriter::write(const ImageView& image, const FrameRecord& record) {
  if (finished_) throw std::logic_error("FrameLogWriter::write after finish");
  if (!to_frame_message(image, record, message_)) {
    prepare_frame_message(message_, image.width, image.height, image.format);
    to_frame_message(image, record, message_);
  }
  bytes_.resize(static_cast<std::size_t>(message_.getEncodedSize()));
  const int size = message_.encode(bytes_.data(), 0, static_cast<int>(bytes_.size()));
  lcm::LogEvent event;
  event.eventnum = 0;  // LCM numbers the events it writes
  event.timestamp = record.utime;
  event.channel = channel_;
  event.datalen = size;
  event.data = bytes_.data();
  // Flushed per event (a frame is large anyway), so that a full disk costs at most the
  // event being written.
  FILE* file = log_->getFilePtr();
  if (size < 0 || log_->writeEvent(&event) != 0 || std::fflush(file) != 0)
    throw FrameLogError(tmp_ + ": cannot write frame " + std::to_string(record.sequence) + ": " + std::strerror(errno));
  whole_bytes_ = ::ftello(file);
  ++frames_;
}

void FrameLogWriter::finish() {
  if (finished_) return;
  FILE* file = log_->getFilePtr();
  const bool flushed = std::fflush(file) == 0 && !std::ferror(file) && ::fsync(::fileno(file)) == 0;
  const int error = errno;
  if (!flushed) throw FrameLogError(tmp_ + ": write failed: " + std::strerror(error));  // keep_written() may still cut
  log_.reset();
  if (::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw FrameLogError(path_ + ": cannot rename into place: " + std::strerror(errno));
  finished_ = true;
}

std::string FrameLogWriter::keep_written() noexcept {
  if (finished_ || !log_) return finished_ ? "" : "nothing to keep";
  FILE* file = log_->getFilePtr();
  std::fflush(file);  // fails again on a full disk: the cut below drops what it left
  const int fd = ::fileno(file);
  std::string why;
  if (::ftruncate(fd, whole_bytes_) != 0 || ::fsync(fd) != 0)
    why = tmp_ + ": cannot cut back to whole events: " + std::strerror(errno);
  log_.reset();
  if (why.empty() && ::rename(tmp_.c_str(), path_.c_str()) != 0)
    why = path_ + ": cannot rename into place: " + std::strerror(errno);
  finished_ = why.empty();
  return why;
}

FrameLogReader::FrameLogReader(std::string path, std::string channel)
    : path_(std::move(path)), channel_(std::move(channel)) {
  struct stat st {};
  if (::stat(path_.c_str(), &st) != 0) throw FrameLogError(path_ + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw FrameLogError(path_ + ": not a file");
  // A file with no event at its start is not a damaged log but something else: say so
  // rather than scan it all for a sync word.
  if (!starts_with_lcm_event(path_)) throw FrameLogError(path_ + ": not an LCM log (no LCM event at its start)");
  fd_.reset(::open(path_.c_str(), O_RDONLY | O_CLOEXEC));
  if (!fd_) throw FrameLogError(path_ + ": " + std::strerror(errno));
  scanner_ = std::make_unique<LcmLogScanner>(fd_.get());
  if (!scanner_->error().empty()) throw FrameLogError(path_ + ": " + scanner_->error());
}

FrameLogReader::~FrameLogReader() = default;

FrameLogReader::Next FrameLogReader::next() {
  for (;;) {
    // The scanner skips damage on its way to the next valid event: report the skip
    // first, then that event on the following call.
    if (!pending_event_) {
      const bool more = scanner_->next();
      if (!scanner_->error().empty()) {
        problem_ = path_ + ": read error: " + scanner_->error();
        throw FrameLogError(problem_);
      }
      if (scanner_->damaged_regions() > regions_reported_) {
        regions_reported_ = scanner_->damaged_regions();
        pending_event_ = more;
        problem_ = path_ + ": damaged: " + scanner_->last_damage();
        return Next::lost;
      }
      if (!more) {
        if (scanner_->truncated_tail() && !tail_reported_) {
          tail_reported_ = true;
          problem_ = path_ + ": " + scanner_->last_damage();
          return Next::lost;
        }
        return Next::end;
      }
    }
    pending_event_ = false;
    const LcmLogEvent& event = scanner_->event();
    const std::size_t index = events_++;  // counted here: appended logs restart LCM's eventnum
    if (event.channel != channel_) {
      ++other_events_;
      continue;
    }
    ++frames_;
    record_ = FrameRecord{};
    const std::string where = path_ + ": event " + std::to_string(index) + " on " + channel_ + ": ";
    const int length = static_cast<int>(event.data.size());
    // A message shorter than its event is as damaged as one that does not decode.
    if (message_.decode(event.data.data(), 0, length) != length) {
      problem_ = where + "not a ccdlane.frame_t message (wrong type or damaged)";
      return Next::damaged;
    }
    record_ = frame_record(message_);
    if (std::string why = frame_image(message_, image_); !why.empty()) {
      problem_ = where + why;
      return Next::damaged;
    }
    problem_.clear();
    return Next::frame;
  }
}

}  // namespace ccdlane
