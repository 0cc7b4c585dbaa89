#include "core/log.h"

#include <mutex>
#include <utility>

namespace mbao {
namespace {

std::mutex& sink_mutex() {
  static std::mutex mutex;
  return mutex;
}

LogSink& sink() {
  static LogSink* installed = new LogSink;  // never destroyed: messages may come during static destruction
  return *installed;
}

}  // namespace

void set_log_sink(LogSink new_sink) {
  std::lock_guard<std::mutex> lock(sink_mutex());
  sink() = std::move(new_sink);
}

void log_message(const std::string& message) {
  LogSink current;
  {
    std::lock_guard<std::mutex> lock(sink_mutex());
    current = sink();
  }
  if (current) current(message);
}

}  // namespace mbao
