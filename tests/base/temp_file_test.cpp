// The temporaries of atomic writes: a new name beside the target each time, readable by
// others, never a symlink's target nor a file that was already there.
#include "base/temp_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

std::string contents(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(TempFile, IsANewFileBesideThePath) {
  test::TempDir dir;
  const std::string path = dir.file("state.toml");
  char a[PATH_MAX], b[PATH_MAX];
  const int fa = create_temp_beside(path.c_str(), a, sizeof a);
  const int fb = create_temp_beside(path.c_str(), b, sizeof b);
  ASSERT_GE(fa, 0);
  ASSERT_GE(fb, 0);
  EXPECT_NE(std::string(a), std::string(b));
  EXPECT_EQ(std::string(a).rfind(path + ".tmp.", 0), 0u) << a;
  struct stat st {};
  ASSERT_EQ(::fstat(fa, &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644u);
  ::close(fa);
  ::close(fb);
}

TEST(TempFile, ASymlinkOrAFileAtTheOldTemporaryNameIsLeftAlone) {
  test::TempDir dir;
  const std::string path = dir.file("000000.pgm");
  dir.write("victim", "mine");
  std::filesystem::create_symlink(dir.file("victim"), path + ".tmp");
  char tmp[PATH_MAX];
  const int fd = create_temp_beside(path.c_str(), tmp, sizeof tmp);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::write(fd, "new", 3), 3);
  ::close(fd);
  EXPECT_EQ(contents(dir.file("victim")), "mine");
  EXPECT_TRUE(std::filesystem::is_symlink(path + ".tmp"));
}

TEST(TempFile, ANameThatDoesNotFitIsRefused) {
  char tmp[16];
  EXPECT_EQ(create_temp_beside("/tmp/a-long-name", tmp, sizeof tmp), -ENAMETOOLONG);
}

}  // namespace
}  // namespace ccdlane
