#include "opencl/stderr_capture.h"

#include <unistd.h>

namespace mbao {
namespace {

std::mutex& capture_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

StderrCapture::StderrCapture() : lock_(capture_mutex()) {
  std::fflush(stderr);
  held_ = std::tmpfile();
  if (!held_) return;
  saved_ = dup(STDERR_FILENO);
  if (saved_ < 0 || dup2(fileno(held_), STDERR_FILENO) < 0) {
    if (saved_ >= 0) close(saved_);
    saved_ = -1;
    std::fclose(held_);
    held_ = nullptr;
  }
}

StderrCapture::~StderrCapture() { release(); }

std::string StderrCapture::release() {
  if (!held_) return {};
  std::fflush(stderr);
  dup2(saved_, STDERR_FILENO);
  close(saved_);
  std::string text;
  std::rewind(held_);
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, held_)) > 0;) text.append(buffer, n);
  std::fclose(held_);
  held_ = nullptr;
  return text;
}

}  // namespace mbao
