// Checked flushes and atomically renamed output files of the ccdlane subcommands.
#include "tools/ccdlane/checked_output.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "base/temp_file.hpp"

namespace ccdlane::cli {
namespace {

std::string reason(int error) { return error ? std::strerror(error) : "the data could not be written"; }

}  // namespace

void flush_checked(std::ostream& out, const std::string& what) {
  errno = 0;
  out.flush();
  bool ok = static_cast<bool>(out);
  int error = errno;
  if (&out == &std::cout) {
    errno = 0;
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      ok = false;
      if (errno) error = errno;
    }
  }
  if (!ok) throw std::runtime_error(what + ": cannot write: " + reason(error));
}

void check_written(std::ostream& out, const std::string& what) {
  if (!out) throw std::runtime_error(what + ": cannot write: " + reason(errno));
}

void write_file_checked(const std::string& path, const std::string& text) {
  OutputFile file(path);
  file.stream() << text;
  file.commit();
}

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
  struct stat st {};
  in_place_ = ::stat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
  if (!in_place_ && (tmp_ = new_temp_beside(path_)).empty())
    throw std::runtime_error(path_ + ": cannot create a temporary beside it: " + reason(errno));
  errno = 0;
  stream_.open(in_place_ ? path_ : tmp_, std::ios::binary | std::ios::trunc);
  if (!stream_) throw std::runtime_error((in_place_ ? path_ : tmp_) + ": cannot create: " + reason(errno));
}

OutputFile::~OutputFile() {
  if (committed_ || in_place_) return;
  stream_.close();
  std::remove(tmp_.c_str());
}

void OutputFile::commit() {
  flush_checked(stream_, in_place_ ? path_ : tmp_);
  errno = 0;
  stream_.close();
  if (stream_.fail()) throw std::runtime_error((in_place_ ? path_ : tmp_) + ": cannot write: " + reason(errno));
  if (in_place_) {
    committed_ = true;
    return;
  }
  // The data on disk before the name points at it: a crash leaves the old file or the new.
  if (const int fd = ::open(tmp_.c_str(), O_RDONLY | O_CLOEXEC); fd >= 0) {
    const bool synced = ::fsync(fd) == 0;
    const int error = errno;
    ::close(fd);
    if (!synced) throw std::runtime_error(tmp_ + ": cannot write: " + reason(error));
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw std::runtime_error(path_ + ": cannot rename " + tmp_ + " onto it: " + reason(errno));
  committed_ = true;
}

}  // namespace ccdlane::cli
