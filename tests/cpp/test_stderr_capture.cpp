// What an OpenCL compiler prints to standard error is held back for the log,
// and standard error is the process's own again afterwards; the log's sink
// gets each message, and without a sink messages are dropped.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/log.h"
#include "opencl/stderr_capture.h"

namespace mbao {
namespace {

ino_t stderr_inode() {
  struct stat s {};
  fstat(STDERR_FILENO, &s);
  return s.st_ino;
}

TEST(StderrCapture, HoldsBackWhatIsPrintedAndRestoresStderr) {
  const ino_t before = stderr_inode();
  std::string text;
  {
    StderrCapture capture;
    EXPECT_NE(stderr_inode(), before);
    std::fprintf(stderr, "3 warnings");
    ASSERT_EQ(write(STDERR_FILENO, " generated.\n", 12), 12);  // as LLVM writes: to the descriptor
    text = capture.release();
    EXPECT_EQ(stderr_inode(), before);
  }
  EXPECT_EQ(text, "3 warnings generated.\n");
  EXPECT_EQ(stderr_inode(), before);
  StderrCapture quiet;
  EXPECT_EQ(quiet.release(), "");
}

TEST(Log, HandsMessagesToTheSinkAndDropsThemWithoutOne) {
  std::vector<std::string> received;
  set_log_sink([&](const std::string& message) { received.push_back(message); });
  log_message("one");
  set_log_sink({});
  log_message("two");
  EXPECT_EQ(received, std::vector<std::string>{"one"});
}

}  // namespace
}  // namespace mbao
