// Runs a program and collects its exit status, stdout and stderr: for tests of the
// command-line tools as a user (or a script) calls them.
#pragma once

#include <string>
#include <vector>

namespace ccdlane::test {

struct ProcessResult {
  int exit_status = -1;  // -1 when it did not exit normally
  std::string out;
  std::string err;
};

ProcessResult run_process(const std::vector<std::string>& argv, const std::string& stdin_text = "");

// The whole of file `path`, byte for byte; "" when it cannot be read.
std::string read_file(const std::string& path);

// A fresh directory under the test temp dir, removed when the object goes away.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  // Writes `text` to `name` inside the directory and returns the full path.
  std::string write(const std::string& name, const std::string& text) const;

 private:
  std::string path_;
};

}  // namespace ccdlane::test
