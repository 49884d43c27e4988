// Regular files only, opened without blocking: a real FIFO (with no writer, which would
// block a plain open() for ever), a directory and a device are refused at once; a file
// larger than the bound is refused before it is read whole.
#include "base/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

TEST(RegularFile, OpensAndReadsARegularFileWhole) {
  test::TempDir dir;
  dir.write("a.csv", "file,t_ns\n");
  struct stat st {};
  const int fd = open_regular_file(dir.file("a.csv").c_str(), &st);
  ASSERT_GE(fd, 0);
  EXPECT_EQ(st.st_size, 10);
  EXPECT_EQ(::fcntl(fd, F_GETFL) & O_NONBLOCK, 0) << "reads block again, as on any file";
  ::close(fd);
  std::string text;
  EXPECT_EQ(read_regular_file(dir.file("a.csv"), 10, text), 0);
  EXPECT_EQ(text, "file,t_ns\n");
}

TEST(RegularFile, AFifoADirectoryAndADeviceAreRefusedWithoutBlocking) {
  test::TempDir dir;
  const std::string fifo = dir.file("frames.csv");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(open_regular_file(fifo.c_str()), -EINVAL);
  std::string text;
  EXPECT_EQ(read_regular_file(fifo, 1000, text), -EINVAL);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1)) << "no writer, and no wait for one";
  EXPECT_EQ(open_regular_file(dir.path().c_str()), -EINVAL);
  EXPECT_EQ(open_regular_file("/dev/zero"), -EINVAL) << "endless";
  EXPECT_EQ(open_regular_file(dir.file("absent").c_str()), -ENOENT);
  EXPECT_STREQ(regular_file_error(-EINVAL), "not a regular file");
}

TEST(RegularFile, AFileLargerThanTheBoundIsRefused) {
  test::TempDir dir;
  dir.write("big", std::string(4097, 'x'));
  std::string text;
  EXPECT_EQ(read_regular_file(dir.file("big"), 4096, text), -EFBIG);
  EXPECT_EQ(read_regular_file(dir.file("big"), 4097, text), 0);
  EXPECT_STREQ(regular_file_error(-EFBIG), "too large");
}

}  // namespace
}  // namespace ccdlane
