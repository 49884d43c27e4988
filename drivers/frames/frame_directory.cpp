// Frame directory reader: the index is built once (allocating), reads never allocate.
#include "drivers/frames/frame_directory.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>

#include "base/regular_file.hpp"

namespace ccdlane {
namespace {

// frames.csv of a day's drive at 60 fps is some 30 MB: far more is not a recording.
constexpr std::size_t kMaxFramesCsvBytes = std::size_t{1} << 30;

}  // namespace

FrameDirectory::FrameDirectory(std::string dir) : dir_(std::move(dir)) {
  while (dir_.size() > 1 && dir_.back() == '/') dir_.pop_back();
  csv_path_ = dir_ + "/frames.csv";
  // A regular file only, read without blocking: a FIFO here must not hang replay.
  std::string text;
  if (const int rc = read_regular_file(csv_path_, kMaxFramesCsvBytes, text); rc < 0)
    throw FrameDirectoryError(csv_path_ + ": cannot read: " + regular_file_error(rc) +
                              (rc == -EFBIG ? " (over 1 GB)" : "") + " (a frame directory needs frames.csv)");
  csv_ = parse_frames_csv(text, csv_path_);
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
