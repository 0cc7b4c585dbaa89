// Holds back what the process writes to its standard error while one lives:
// OpenCL compilers print diagnostics there themselves (PoCL's clang its "N
// warnings generated."), which belong in the build log, not on the user's
// terminal. One capture at a time in the process; others wait.
#pragma once

#include <cstdio>
#include <mutex>
#include <string>

namespace mbao {

class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Ends the capture, restoring standard error, and returns what was written
  // during it. Empty where the capture could not start (no temporary file).
  std::string release();

 private:
  std::unique_lock<std::mutex> lock_;
  std::FILE* held_ = nullptr;  // where fd 2 points while capturing
  int saved_ = -1;             // the original fd 2
};

}  // namespace mbao
