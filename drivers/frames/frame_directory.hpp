// Reading a frame directory (docs/interfaces.md "Frame directories"): frames.csv indexed once,
// then each frame (PGM, PPM, PNG or JPEG, told apart by the file's extension) decoded on demand
// into a caller's fixed buffer. A folder of pictures without frames.csv (a benchmark's
// stills, a camera's snapshots) is read in name order.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/frames/frames_csv.hpp"
#include "drivers/frames/jpeg.hpp"
#include "drivers/frames/pgm.hpp"
#include "drivers/frames/png.hpp"

namespace ccdlane {

class FrameDirectory {
 public:
  // Reads DIR/frames.csv. Throws FrameDirectoryError when there is no usable index
  // (an unreadable frames.csv, a header without file or t_ns; no frames.csv and no
  // pictures). Malformed rows are not fatal: they are skipped and listed in issues().
  // Without frames.csv, DIR's pictures (.png, .jpg, .jpeg, .pgm, .ppm, any case) are the
  // frames in name order, kPictureFolderFrameNs apart, and note() says so.
  explicit FrameDirectory(std::string dir);

  // 25 frames a second, as the development drives: a still's time matters to nothing
  // but tracking, and a folder of pictures says none.
  static constexpr std::int64_t kPictureFolderFrameNs = 40'000'000;
  // "DIR: no frames.csv: its N pictures in name order, 40 ms apart", or "" with frames.csv.
  const std::string& note() const { return note_; }

  const std::string& path() const { return dir_; }
  const std::string& csv_path() const { return csv_path_; }

  // The well-formed rows, in time order.
  std::size_t size() const { return csv_.rows.size(); }
  const FrameRow& row(std::size_t i) const { return csv_.rows[i]; }
  const std::string& file_path(std::size_t i) const { return paths_[i]; }
  std::size_t data_rows() const { return csv_.data_rows; }  // including malformed ones
  bool has_gyro_columns() const { return csv_.has_gyro_columns; }
  bool has_vehicle_columns() const { return csv_.has_vehicle_columns; }

  // One message per skipped row of frames.csv ("DIR/frames.csv:7: t_ns: not an integer").
  const std::vector<std::string>& issues() const { return csv_.issues; }

  // truth_* columns, kept by name for tests.
  const std::vector<std::string>& truth_columns() const { return csv_.truth_columns; }
  int truth_column(std::string_view name) const;  // -1 when absent
  // The value of truth column `column` at row i: NaN when the cell is empty.
  double truth(std::size_t i, int column) const;
  std::optional<double> truth(std::size_t i, std::string_view name) const;

  // Decodes row i into `into` (its width, height and format are what frames must be).
  // Allocation-free; on failure error() is "<file path>: <reason>".
  PgmFault read(std::size_t i, const MutableImageView& into, PgmHeader* header = nullptr) {
    last_codec_ = codec_[i];
    switch (last_codec_) {
      case Codec::png: return png_reader_.read(paths_[i].c_str(), into, header);
      case Codec::jpeg: return jpeg_reader_.read(paths_[i].c_str(), into, header);
      case Codec::pgm: break;
    }
    return reader_.read(paths_[i].c_str(), into, header);
  }
  std::string_view error() const {
    return last_codec_ == Codec::png    ? png_reader_.error()
           : last_codec_ == Codec::jpeg ? jpeg_reader_.error()
                                        : reader_.error();
  }

  // The header of the first frame whose header reads: the directory's frame size and
  // depth when the configuration does not fix them. Empty when no frame has one.
  std::optional<PgmHeader> probe_first();

 private:
  // The frames of a folder without frames.csv; false when it has no pictures either.
  bool index_pictures();

  std::string dir_;
  std::string csv_path_;
  std::string note_;
  FramesCsv csv_;
  std::vector<std::string> paths_;
  // By the file's extension: ".png" is PNG, ".jpg"/".jpeg" JPEG, anything else PGM or PPM.
  enum class Codec : std::uint8_t { pgm, png, jpeg };
  std::vector<Codec> codec_;
  PgmReader reader_;
  PngReader png_reader_;
  JpegReader jpeg_reader_;
  Codec last_codec_ = Codec::pgm;  // which reader's error() is the last one
};

}  // namespace ccdlane
