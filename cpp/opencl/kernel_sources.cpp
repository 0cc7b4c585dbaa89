#include "opencl/kernel_sources.h"

#include <set>
#include <sstream>
#include <stdexcept>

namespace mbao {
namespace {

void expand(const std::string& name, std::set<std::string>& included, std::string& out) {
  const auto& files = embedded_kernel_files();
  const auto file = files.find(name);
  if (file == files.end()) throw std::logic_error("kernel source not embedded: " + name);
  if (!included.insert(name).second) return;
  std::istringstream lines{std::string(file->second)};
  for (std::string line; std::getline(lines, line);) {
    const auto directive = line.find("#include \"");
    if (directive != std::string::npos && line.find_first_not_of(" \t") == directive) {
      const auto start = directive + 10;
      expand(line.substr(start, line.find('"', start) - start), included, out);
    } else {
      out += line;
      out += '\n';
    }
  }
}

}  // namespace

std::string kernel_program_source(const std::string& name) {
  std::set<std::string> included;
  std::string out;
  expand(name, included, out);
  return out;
}

}  // namespace mbao
