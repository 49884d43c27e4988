// LCM log framing: header checks, resynchronisation after damage, and its counters.
#include "bus/lcm_log_scanner.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ccdlane {
namespace {

constexpr unsigned char kSync[4] = {0xED, 0xA1, 0xDA, 0x01};
constexpr std::size_t kChunkBytes = 64 * 1024;

std::uint64_t big_endian(const unsigned char* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

LcmLogScanner::LcmLogScanner(int fd, std::int64_t max_data_bytes)
    : fd_(fd), max_data_bytes_(std::clamp<std::int64_t>(max_data_bytes, 0, kLcmLogMaxDataBytes)) {
  struct stat st {};
  if (::fstat(fd_, &st) != 0)
    error_ = std::strerror(errno);
  else if (st.st_size > 0)
    file_size_ = static_cast<std::uint64_t>(st.st_size);
}

bool LcmLogScanner::read_at(std::uint64_t at, void* into, std::size_t n) {
  auto* p = static_cast<unsigned char*>(into);
  while (n > 0) {
    const ssize_t got = ::pread(fd_, p, n, static_cast<off_t>(at));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      if (error_.empty()) error_ = std::strerror(errno);
      return false;
    }
    if (got == 0) return false;  // the file shrank under us
    p += got, at += static_cast<std::uint64_t>(got), n -= static_cast<std::size_t>(got);
  }
  return true;
}

bool LcmLogScanner::sync_at(std::uint64_t at) {
  unsigned char word[4];
  return at + 4 <= file_size_ && read_at(at, word, 4) && std::memcmp(word, kSync, 4) == 0;
}

std::uint64_t LcmLogScanner::find_sync(std::uint64_t from) {
  chunk_.resize(kChunkBytes);
  while (from + 4 <= file_size_) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunkBytes, file_size_ - from));
    if (!read_at(from, chunk_.data(), n)) return file_size_;
    for (std::size_t i = 0; i + 4 <= n; ++i) {
      const void* hit = std::memchr(chunk_.data() + i, kSync[0], n - i);
      if (!hit) break;
      i = static_cast<std::size_t>(static_cast<const std::uint8_t*>(hit) - chunk_.data());
      if (i + 4 > n) break;
      if (std::memcmp(chunk_.data() + i, kSync, 4) == 0) return from + i;
    }
    if (n < 4 || from + n >= file_size_) break;
    from += n - 3;  // a word across the chunk boundary is found in the next chunk
  }
  return file_size_;
}

LcmLogScanner::Header LcmLogScanner::check_header(std::uint64_t at, LcmLogEvent& out, std::string& why,
                                                  std::size_t& data_bytes_out) {
  const std::uint64_t left = file_size_ - at;
  unsigned char h[kLcmLogHeaderBytes];
  if (left < 4 || !sync_at(at)) {
    why = "no sync word";
    return Header::invalid;
  }
  if (left < kLcmLogHeaderBytes) {
    why = "the file ends inside an event header";
    return Header::truncated;
  }
  if (!read_at(at, h, sizeof h)) {
    why = "cannot read the event header";
    return Header::invalid;
  }
  const auto eventnum = static_cast<std::int64_t>(big_endian(h + 4, 8));
  const auto timestamp = static_cast<std::int64_t>(big_endian(h + 12, 8));
  const auto channel_bytes = static_cast<std::int32_t>(big_endian(h + 20, 4));
  const auto data_bytes = static_cast<std::int32_t>(big_endian(h + 24, 4));
  if (eventnum < 0) {
    why = "negative event number " + std::to_string(eventnum);
    return Header::invalid;
  }
  if (timestamp < 0) {
    why = "negative timestamp " + std::to_string(timestamp);
    return Header::invalid;
  }
  if (channel_bytes <= 0 || channel_bytes > kLcmLogMaxChannelBytes) {
    why = "channel length " + std::to_string(channel_bytes) + " is not within 1.." +
          std::to_string(kLcmLogMaxChannelBytes);
    return Header::invalid;
  }
  if (data_bytes < 0 || data_bytes > max_data_bytes_) {
    why = "data length " + std::to_string(data_bytes) + " is not within 0.." + std::to_string(max_data_bytes_);
    return Header::invalid;
  }
  const std::uint64_t channel_end = kLcmLogHeaderBytes + static_cast<std::uint64_t>(channel_bytes);
  out.channel.resize(static_cast<std::size_t>(channel_bytes));
  if (channel_end > left) {
    why = "the file ends inside an event's channel name";
    return Header::truncated;
  }
  if (!read_at(at + kLcmLogHeaderBytes, out.channel.data(), out.channel.size())) {
    why = "cannot read the channel name";
    return Header::invalid;
  }
  for (const char c : out.channel)
    if (c < 0x21 || c > 0x7E) {
      why = "the channel name holds a byte that is not printable ASCII";
      return Header::invalid;
    }
  if (channel_end + static_cast<std::uint64_t>(data_bytes) > left) {
    why = "data length " + std::to_string(data_bytes) + " is more than the " + std::to_string(left - channel_end) +
          " bytes left in the file";
    return Header::truncated;
  }
  out.offset = at;
  out.eventnum = eventnum;
  out.timestamp = timestamp;
  data_bytes_out = static_cast<std::size_t>(data_bytes);  // bounded above by the file and the limit
  return Header::valid;
}

std::uint64_t LcmLogScanner::valid_event_inside(std::uint64_t data_at, const std::vector<std::uint8_t>& data) {
  LcmLogEvent scratch;
  std::string ignored;
  std::size_t scratch_bytes = 0;
  const std::uint8_t* p = data.data();
  const std::uint8_t* const end = p + data.size();
  while (end - p >= 4) {
    p = static_cast<const std::uint8_t*>(std::memchr(p, kSync[0], static_cast<std::size_t>(end - p)));
    if (!p || end - p < 4) break;
    if (std::memcmp(p, kSync, 4) == 0) {
      const std::uint64_t at = data_at + static_cast<std::uint64_t>(p - data.data());
      if (check_header(at, scratch, ignored, scratch_bytes) == Header::valid) return at;
    }
    ++p;
  }
  // A sync word may also begin in the last three bytes and run past the data.
  const std::uint64_t data_end = data_at + data.size();
  for (std::uint64_t at = data_end - std::min<std::uint64_t>(3, data.size()); at < data_end; ++at)
    if (check_header(at, scratch, ignored, scratch_bytes) == Header::valid) return at;
  return 0;
}

void LcmLogScanner::skip_region(std::uint64_t from, std::uint64_t to, const std::string& why) {
  std::uint64_t events = 1;
  for (std::uint64_t s = find_sync(from + 1); s < to; s = find_sync(s + 1)) ++events;
  ++damaged_regions_;
  events_lost_ += events;
  bytes_skipped_ += to - from;
  last_damage_ = "bytes " + std::to_string(from) + ".." + std::to_string(to) + " (" + std::to_string(to - from) +
                 " bytes, about " + std::to_string(events) + (events == 1 ? " event" : " events") + ") skipped: " + why;
}

bool LcmLogScanner::next() {
  LcmLogEvent scratch;
  std::string why, ignored;
  std::size_t data_bytes = 0, scratch_bytes = 0;
  while (position_ < file_size_ && error_.empty()) {
    const Header header = check_header(position_, event_, why, data_bytes);
    if (header == Header::valid) {
      event_.data.resize(data_bytes);
      const std::uint64_t data_at = position_ + kLcmLogHeaderBytes + event_.channel.size();
      if (!read_at(data_at, event_.data.data(), event_.data.size())) return false;
      // A length changed to another plausible value swallows the start of the next
      // event: a valid event inside this one's data means its length is what is wrong.
      if (const std::uint64_t inner = valid_event_inside(data_at, event_.data); inner != 0) {
        skip_region(position_, inner, "its length runs past the start of the next event");
        position_ = inner;
        continue;
      }
      position_ = data_at + event_.data.size();
      return true;
    }
    std::uint64_t resume = find_sync(position_ + 1);
    while (resume < file_size_ && check_header(resume, scratch, ignored, scratch_bytes) != Header::valid)
      resume = find_sync(resume + 1);
    if (header == Header::truncated && resume == file_size_) {
      truncated_tail_ = true;
      truncated_tail_bytes_ = file_size_ - position_;
      ++events_lost_;
      bytes_skipped_ += truncated_tail_bytes_;
      last_damage_ = "the last event (at byte " + std::to_string(position_) + ") is cut short: " + why;
      position_ = file_size_;
      return false;
    }
    skip_region(position_, resume, why);
    position_ = resume;
  }
  return false;
}

}  // namespace ccdlane
