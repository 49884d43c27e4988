// Opening and reading files that must be regular files: a FIFO where a frame, frames.csv
// or the state file is expected would block open() for ever (and with it a thread that
// must stop on SIGTERM), and a device would be read without end. Both are refused before
// a byte is read.
#pragma once

#include <sys/stat.h>

#include <cstddef>
#include <string>

namespace ccdlane {

// Opens `path` read-only and close-on-exec without blocking (O_NONBLOCK: a FIFO without
// a writer opens at once), checks with fstat that it is a regular file, then clears
// O_NONBLOCK. The fd, or -errno: open()'s, or -EINVAL for anything but a regular file (a
// FIFO, a device, a directory, a socket). `st`, when given, gets the file's stat.
// Allocates nothing.
int open_regular_file(const char* path, struct stat* st = nullptr);

// The whole of a regular file of at most max_bytes into `out`. 0, or -errno:
// open_regular_file()'s, -EFBIG when it holds more than max_bytes, or a read's.
int read_regular_file(const std::string& path, std::size_t max_bytes, std::string& out);

// The reason for one of the two functions' results: "not a regular file" (-EINVAL),
// "too large" (-EFBIG), else strerror.
const char* regular_file_error(int rc);

}  // namespace ccdlane
