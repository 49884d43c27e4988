// The learned mount on disk: a small TOML-like text file in the state directory, written
// atomically (temporary file, fsync, rename, fsync of the directory) so that a power cut
// leaves the old file or the new one, never half of one; read back and validated at start.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/lane/online_mount_refiner.hpp"

namespace ccdlane {

inline constexpr int kMountStateFormat = 1;
inline constexpr const char* kMountStateFileName = "mount-refinement.toml";

// The file's text for `learned`, learned against the mount in `options`, into `out`
// (1 KiB is plenty). Returns the length, or 0 when it did not fit. No allocation.
std::size_t format_mount_state(const calibration::LearnedMount& learned, const calibration::OnlineMountOptions& options,
                               char* out, std::size_t size);

// Reads a file's text into `learned`: "" when it is a mount learned against the mount in
// `options` (format version, every key once, finite numbers, corrections within
// max_correction_deg), else why not, in a few words.
std::string parse_mount_state(std::string_view text, const calibration::OnlineMountOptions& options,
                              calibration::LearnedMount& learned);

// What went wrong writing a file: the failing step ("open", "write", "fsync", "rename",
// ...) and its errno; step null when it went well.
struct FileWriteError {
  const char* step = nullptr;
  int error = 0;
  explicit operator bool() const { return step != nullptr; }
};

// `data` to `path` by way of a new temporary file beside it (base/temp_file.hpp: never
// a symlink's target, never a file already there), then rename. No allocation: the
// daemon's status thread writes with it after READY.
FileWriteError write_file_atomically(const char* path, const char* data, std::size_t size);

}  // namespace ccdlane
