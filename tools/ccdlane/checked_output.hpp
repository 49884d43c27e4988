// Output that is known to have been written: every ccdlane subcommand that writes goes
// through these, so a full disk or a closed pipe is an error (exit 1), never exit 0.
#pragma once

#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>

namespace ccdlane::cli {

// Flushes `out` (for std::cout also C's stdout, which printf shares) and throws
// std::runtime_error "<what>: cannot write: <reason>" if anything written to it was lost.
void flush_checked(std::ostream& out, const std::string& what);

// Right after writing to `out`: throws the same error once `out` has failed, with the
// reason the failed write left in errno (a later flush no longer knows it, when the
// write that failed was one of many).
void check_written(std::ostream& out, const std::string& what);

// Writes `text` to `path` through OutputFile and commits it.
void write_file_checked(const std::string& path, const std::string& text);

// An output file written under a new PATH.tmp.XXXXXX (base/temp_file.hpp) and renamed
// onto PATH by commit(), after a checked flush and fsync: the file is whole or absent. A PATH that exists and is not a
// regular file (a device, a FIFO) is written in place. Destroyed without commit(), the
// temporary file is removed.
class OutputFile {
 public:
  explicit OutputFile(std::string path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::ostream& stream() { return stream_; }
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_;
  std::ofstream stream_;
  bool in_place_ = false, committed_ = false;
};

}  // namespace ccdlane::cli
