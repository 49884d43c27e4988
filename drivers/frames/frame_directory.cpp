// Frame directory reader: the index is built once (allocating), reads never allocate.
#include "drivers/frames/frame_directory.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "base/regular_file.hpp"

namespace ccdlane {
namespace {

// frames.csv of a day's drive at 60 fps is some 30 MB: far more is not a recording.
constexpr std::size_t kMaxFramesCsvBytes = std::size_t{1} << 30;

// A picture the frame readers take, by the extension they are told apart by (the
// codecs' own tests for PNG and JPEG; PGM and PPM, any case), with a name before it.
// Hidden files are not frames: a folder copied from a Mac holds a `._0001.jpg` (its
// AppleDouble metadata, not a JPEG) beside each picture, which would play as a damaged
// frame after every good one.
bool is_picture_name(std::string_view name) {
  const std::size_t dot = name.rfind('.');
  if (name.starts_with('.') || dot == std::string_view::npos) return false;
  const std::string_view ext = name.substr(dot);
  const auto pnm = ext.size() == 4 && (ext[1] | 0x20) == 'p' && ((ext[2] | 0x20) == 'g' || (ext[2] | 0x20) == 'p') &&
                   (ext[3] | 0x20) == 'm';
  return pnm || has_png_extension(name) || has_jpeg_extension(name);
}

// Name order as a person reads it: runs of digits by their value, so that a clip's
// 1.jpg ... 20.jpg (TuSimple's) play 2 before 10; the rest byte by byte.
bool before_in_name_order(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && a[ie] == '0') ++ie;  // leading zeros say nothing of the value
      while (je < b.size() && b[je] == '0') ++je;
      std::size_t ia = ie, jb = je;
      while (ia < a.size() && digit(a[ia])) ++ia;
      while (jb < b.size() && digit(b[jb])) ++jb;
      if (ia - ie != jb - je) return ia - ie < jb - je;  // fewer digits: smaller
      if (const int c = a.compare(ie, ia - ie, b, je, jb - je); c != 0) return c < 0;
      i = ia, j = jb;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  if (a.size() - i != b.size() - j) return a.size() - i < b.size() - j;
  return a < b;  // equal values written differently (01 and 1): a fixed order all the same
}

}  // namespace

bool FrameDirectory::index_pictures() {
  std::vector<std::string> names;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec) && is_picture_name(it->path().filename().string()))
      names.push_back(it->path().filename().string());
  if (names.empty()) return false;
  std::sort(names.begin(), names.end(), before_in_name_order);
  for (std::size_t i = 0; i < names.size(); ++i) {
    FrameRow row;
    row.index = i;
    row.file = names[i];
    row.t_ns = static_cast<std::int64_t>(i) * kPictureFolderFrameNs;
    csv_.rows.push_back(std::move(row));
  }
  csv_.data_rows = names.size();
  note_ = dir_ + ": no frames.csv: its " + std::to_string(names.size()) + " pictures in name order, " +
          std::to_string(kPictureFolderFrameNs / 1'000'000) + " ms apart";
  return true;
}

FrameDirectory::FrameDirectory(std::string dir) : dir_(std::move(dir)) {
  while (dir_.size() > 1 && dir_.back() == '/') dir_.pop_back();
  csv_path_ = dir_ + "/frames.csv";
  // A regular file only, read without blocking: a FIFO here must not hang replay.
  std::string text;
  const int rc = read_regular_file(csv_path_, kMaxFramesCsvBytes, text);
  if (rc >= 0)
    csv_ = parse_frames_csv(text, csv_path_);
  else if (!(rc == -ENOENT && index_pictures()))
    throw FrameDirectoryError(
        csv_path_ + ": cannot read: " + regular_file_error(rc) + (rc == -EFBIG ? " (over 1 GB)" : "") +
        (rc == -ENOENT ? " (a frame directory needs frames.csv, or pictures to take in name order)"
                       : " (a frame directory needs frames.csv)"));
  paths_.reserve(csv_.rows.size());
  for (const FrameRow& r : csv_.rows) {
    paths_.push_back(!r.file.empty() && r.file.front() == '/' ? r.file : dir_ + "/" + r.file);
    codec_.push_back(has_png_extension(r.file) ? Codec::png : has_jpeg_extension(r.file) ? Codec::jpeg : Codec::pgm);
  }
}

int FrameDirectory::truth_column(std::string_view name) const {
  for (std::size_t k = 0; k < csv_.truth_columns.size(); ++k)
    if (csv_.truth_columns[k] == name) return static_cast<int>(k);
  return -1;
}

double FrameDirectory::truth(std::size_t i, int column) const {
  return csv_.truth[i * csv_.truth_columns.size() + static_cast<std::size_t>(column)];
}

std::optional<double> FrameDirectory::truth(std::size_t i, std::string_view name) const {
  const int k = truth_column(name);
  if (k < 0) return std::nullopt;
  const double v = truth(i, k);
  if (std::isnan(v)) return std::nullopt;
  return v;
}

std::optional<PgmHeader> FrameDirectory::probe_first() {
  PgmHeader h;
  for (std::size_t i = 0; i < paths_.size(); ++i) {
    last_codec_ = codec_[i];
    const char* path = paths_[i].c_str();
    const PgmFault f = last_codec_ == Codec::png    ? png_reader_.probe(path, h)
                       : last_codec_ == Codec::jpeg ? jpeg_reader_.probe(path, h)
                                                    : reader_.probe(path, h);
    if (f == PgmFault::none) return h;
  }
  return std::nullopt;
}

}  // namespace ccdlane
