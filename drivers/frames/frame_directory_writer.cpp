// Frame directory writer: temporary names, renames, and clean-up of unfinished work.
#include "drivers/frames/frame_directory_writer.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "base/temp_file.hpp"
#include "drivers/frames/pgm.hpp"
#include "drivers/frames/png.hpp"

namespace ccdlane {
namespace {

// Shortest text that reads back to the same double.
void append_number(std::string& out, double v) {
  if (!std::isfinite(v)) return;  // empty cell
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, ec == std::errc() ? end : buf);
}

// A name in `dir` that the writer would write (frames.csv.tmp, or a frame's "NNNNNN.pgm"
// or ".png"), or "": a user's files there are never replaced, and a directory holding
// such names is refused before a frame is taken rather than half-way through.
std::string name_in_the_way(const std::string& dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const std::size_t dot = name.find('.');
    const std::string stem = name.substr(0, dot), ext = dot == std::string::npos ? "" : name.substr(dot);
    const bool frame_name = stem.size() >= 6 && stem.find_first_not_of("0123456789") == std::string::npos &&
                            (ext == ".pgm" || ext == ".png");
    if (name == "frames.csv.tmp" || frame_name) return name;
  }
  return "";
}

}  // namespace

FrameDirectoryWriter::FrameDirectoryWriter(std::string dir, FrameDirectoryLayout layout)
    : dir_(std::move(dir)), layout_(std::move(layout)) {
  namespace fs = std::filesystem;
  while (dir_.size() > 1 && dir_.back() == '/') dir_.pop_back();
  for (const std::string& c : layout_.truth_columns)
    if (c.rfind("truth_", 0) != 0 || c.find_first_of(",\n\r") != std::string::npos)
      throw FrameDirectoryError(dir_ + ": bad truth column name \"" + c + "\" (must start with truth_)");
  std::error_code ec;
  if (fs::exists(dir_, ec)) {
    if (!fs::is_directory(dir_, ec)) throw FrameDirectoryError(dir_ + ": exists and is not a directory");
    if (fs::exists(dir_ + "/frames.csv", ec))
      throw FrameDirectoryError(dir_ + ": already holds a frame directory (frames.csv); choose another place");
    if (const std::string name = name_in_the_way(dir_); !name.empty())
      throw FrameDirectoryError(dir_ + ": already holds " + name + ", a name a recording writes; choose another place");
  } else {
    created_dir_ = fs::create_directories(dir_, ec);
    if (ec) throw FrameDirectoryError(dir_ + ": cannot create the directory: " + ec.message());
  }
  tmp_csv_ = new_temp_beside(dir_ + "/frames.csv");
  if (!tmp_csv_.empty()) csv_.open(tmp_csv_, std::ios::binary | std::ios::trunc);
  if (tmp_csv_.empty() || !csv_) {
    const std::string what = tmp_csv_.empty() ? dir_ + "/frames.csv.tmp" : tmp_csv_;
    abandon();
    throw FrameDirectoryError(what + ": cannot create");
  }
  std::string header = "file,t_ns";
  if (layout_.gyro) header += ",roll_deg,pitch_deg,yaw_deg";
  for (const std::string& c : layout_.truth_columns) header += "," + c;
  if (layout_.vehicle) header += ",speed_kmh,turn_indicator";
  csv_ << header << '\n';
  csv_.flush();
  csv_bytes_ = csv_.tellp();
}

FrameDirectoryWriter::~FrameDirectoryWriter() {
  if (!finished_) abandon();
}

void FrameDirectoryWriter::abandon() noexcept {
  csv_.close();
  if (!tmp_csv_.empty()) ::unlink(tmp_csv_.c_str());
  for (const std::string& f : files_) ::unlink((dir_ + "/" + f).c_str());
  files_.clear();
  if (created_dir_) ::rmdir(dir_.c_str());  // only if empty: never remove what others put there
}

void FrameDirectoryWriter::write(const ImageView& image, std::int64_t t_ns, const std::optional<Gx1Angles>& gyro,
                                 std::span<const double> truth, const FrameVehicle& vehicle) {
  if (finished_) throw std::logic_error("FrameDirectoryWriter::write after finish");
  if (truth.size() != layout_.truth_columns.size())
    throw std::logic_error("FrameDirectoryWriter::write: truth values do not match the truth columns");
  if (!files_.empty() && t_ns < last_t_ns_)
    throw FrameDirectoryError(dir_ + ": frame " + std::to_string(files_.size()) + ": t_ns goes back in time");
  char name[32];
  const bool colour = is_colour(image.format);
  std::snprintf(name, sizeof name, "%06zu.%s", files_.size(), colour ? "png" : "pgm");
  struct stat st {};
  if (::lstat((dir_ + "/" + name).c_str(), &st) == 0)  // appeared since the start: not ours to replace
    throw FrameDirectoryError(dir_ + "/" + name + ": exists and is not this recording's; not replaced");
  try {
    if (colour)
      write_png(dir_ + "/" + name, image);
    else
      write_pgm(dir_ + "/" + name, image);
  } catch (const std::runtime_error& e) {
    throw FrameDirectoryError(e.what());
  }
  files_.emplace_back(name);
  last_t_ns_ = t_ns;

  std::string row = name;
  row += ',';
  row += std::to_string(t_ns);
  if (layout_.gyro) {
    constexpr double kEmpty = std::numeric_limits<double>::quiet_NaN();
    for (const double v :
         {gyro ? gyro->roll_deg : kEmpty, gyro ? gyro->pitch_deg : kEmpty, gyro ? gyro->yaw_deg : kEmpty}) {
      row += ',';
      append_number(row, v);
    }
  }
  for (const double v : truth) {
    row += ',';
    append_number(row, v);
  }
  if (layout_.vehicle) {
    row += ',';
    append_number(row, vehicle.speed_kmh.value_or(std::numeric_limits<double>::quiet_NaN()));
    row += ',';
    row += to_string(vehicle.indicator);
  }
  csv_ << row << '\n';
  csv_.flush();
  if (!csv_) throw FrameDirectoryError(tmp_csv_ + ": write failed: " + std::strerror(errno));
  csv_bytes_ = csv_.tellp();
  kept_frames_ = files_.size();
}

std::string FrameDirectoryWriter::keep_written() noexcept {
  if (finished_) return "";
  csv_.clear();
  csv_.close();  // may fail again: the row it held is cut off below
  if (::truncate(tmp_csv_.c_str(), csv_bytes_) != 0)
    return tmp_csv_ + ": cannot cut back to whole rows: " + std::strerror(errno);
  // A picture without its row was the frame being written: not part of the recording.
  for (std::size_t i = kept_frames_; i < files_.size(); ++i) ::unlink((dir_ + "/" + files_[i]).c_str());
  files_.resize(kept_frames_);
  const std::string final_csv = dir_ + "/frames.csv";
  if (::rename(tmp_csv_.c_str(), final_csv.c_str()) != 0)
    return final_csv + ": cannot rename into place: " + std::strerror(errno);
  finished_ = true;
  return "";
}

void FrameDirectoryWriter::finish() {
  if (finished_) return;
  csv_.close();
  if (csv_.fail()) throw FrameDirectoryError(tmp_csv_ + ": write failed");
  const std::string final_csv = dir_ + "/frames.csv";
  if (::rename(tmp_csv_.c_str(), final_csv.c_str()) != 0)
    throw FrameDirectoryError(final_csv + ": cannot rename into place");
  finished_ = true;
}

}  // namespace ccdlane
