// The LCM event-log framing read and checked by ccdlane itself, so that no length field
// from disk reaches an allocation unchecked; damage is skipped to the next valid event
// and counted. No liblcm here: the libFuzzer target builds this file alone.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ccdlane {

// One event of an LCM log (lcm/eventlog.c): a 28-byte big-endian header — sync word
// 0xEDA1DA01, int64 event number, int64 timestamp (us), int32 channel length, int32
// data length — then the channel name and the data.
inline constexpr std::uint32_t kLcmLogSyncWord = 0xEDA1DA01u;
inline constexpr std::size_t kLcmLogHeaderBytes = 28;
// LCM itself allows channel names of up to 63 bytes; liblcm's reader up to 999.
inline constexpr std::int32_t kLcmLogMaxChannelBytes = 255;
// The largest frame_t is 8192 x 8192 mono16 (128 MiB); twice that leaves room.
inline constexpr std::int64_t kLcmLogMaxDataBytes = 256LL << 20;

struct LcmLogEvent {
  std::uint64_t offset = 0;  // of its sync word in the file
  std::int64_t eventnum = 0, timestamp = 0;
  std::string channel;
  std::vector<std::uint8_t> data;
};

// Reads the events of an open log file descriptor (not owned) in order. Every length is
// bounded before it is used: by the limits above and by the bytes the file still holds.
// A header that fails a check starts a damaged region, skipped up to the next sync word
// whose header passes; the skipped bytes and the events they held are counted.
class LcmLogScanner {
 public:
  explicit LcmLogScanner(int fd, std::int64_t max_data_bytes = kLcmLogMaxDataBytes);

  // True with event() holding the next valid event; false at the end of the file (or on
  // a read error: error() then says why).
  bool next();
  const LcmLogEvent& event() const { return event_; }

  std::uint64_t file_bytes() const { return file_size_; }
  std::uint64_t damaged_regions() const { return damaged_regions_; }
  std::uint64_t bytes_skipped() const { return bytes_skipped_; }
  // Events lost to damage: one per damaged region (it begins where an event was due),
  // plus each further sync word inside it (an event start that did not check out).
  std::uint64_t events_lost() const { return events_lost_; }
  // The file ends inside an event whose header was valid: its bytes are counted in
  // bytes_skipped() and the event in events_lost(), but it is reported as a cut, not
  // as damage.
  bool truncated_tail() const { return truncated_tail_; }
  std::uint64_t truncated_tail_bytes() const { return truncated_tail_bytes_; }
  // The latest damaged region or cut: where, how long, and what failed first, e.g.
  // "bytes 1440351..1920468 (480117 bytes) skipped: data length 2147483647 is more
  // than 268435456"; empty if none.
  const std::string& last_damage() const { return last_damage_; }
  const std::string& error() const { return error_; }

 private:
  enum class Header : std::uint8_t { valid, invalid, truncated };
  // Fills `out` but its data; `data_bytes` is the data length, checked.
  Header check_header(std::uint64_t at, LcmLogEvent& out, std::string& why, std::size_t& data_bytes);
  bool read_at(std::uint64_t at, void* into, std::size_t n);
  std::uint64_t find_sync(std::uint64_t from);  // file_size_ if none
  bool sync_at(std::uint64_t at);
  // The file offset of the first valid event header inside `data` (read from data_at),
  // or 0 if none.
  std::uint64_t valid_event_inside(std::uint64_t data_at, const std::vector<std::uint8_t>& data);
  void skip_region(std::uint64_t from, std::uint64_t to, const std::string& why);

  int fd_;
  std::int64_t max_data_bytes_;
  std::uint64_t file_size_ = 0, position_ = 0;
  LcmLogEvent event_;
  std::uint64_t damaged_regions_ = 0, bytes_skipped_ = 0, events_lost_ = 0, truncated_tail_bytes_ = 0;
  bool truncated_tail_ = false;
  std::string last_damage_, error_;
  std::vector<std::uint8_t> chunk_;
};

}  // namespace ccdlane
