// Messages for the user that are not errors, such as an OpenCL compiler's
// warnings: handed to the sink the embedding sets (the Python module: its
// logger "mbao"), never printed by the core itself.
#pragma once

#include <functional>
#include <string>

namespace mbao {

using LogSink = std::function<void(const std::string& message)>;

// Replaces the sink; an empty one drops messages. Thread-safe.
void set_log_sink(LogSink sink);
// Hands `message` to the sink, from any thread.
void log_message(const std::string& message);

}  // namespace mbao
