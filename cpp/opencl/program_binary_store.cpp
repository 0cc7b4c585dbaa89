#include "opencl/program_binary_store.h"

#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace mbao {
namespace {

constexpr char kMagic[8] = {'M', 'B', 'A', 'O', 'C', 'L', 'B', '1'};

// FNV-1a, 64 bits: stable across processes, platforms and compilers.
std::uint64_t fnv1a(const unsigned char* data, std::size_t size, std::uint64_t hash = 0xcbf29ce484222325ull) {
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= data[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

std::string hex(std::uint64_t value) {
  std::ostringstream out;
  out.width(16);
  out.fill('0');
  out << std::hex << value;
  return out.str();
}

}  // namespace

std::filesystem::path ProgramBinaryStore::default_directory() {
  if (const char* chosen = std::getenv("MBAO_CACHE_DIR")) return chosen;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "mbao" / "kernels";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "mbao" / "kernels";
  return {};
}

std::filesystem::path ProgramBinaryStore::file_for(const std::string& key) const {
  const auto* bytes = reinterpret_cast<const unsigned char*>(key.data());
  // Two independent 64-bit hashes: 128 bits, so distinct keys do not share a file.
  return directory_ / (hex(fnv1a(bytes, key.size())) + hex(fnv1a(bytes, key.size(), 0x84222325cbf29ce4ull)) + ".bin");
}

std::optional<std::vector<unsigned char>> ProgramBinaryStore::load(const std::string& key) const {
  if (!enabled()) return std::nullopt;
  std::ifstream in(file_for(key), std::ios::binary);
  if (!in) return std::nullopt;
  const std::vector<unsigned char> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::size_t header = sizeof kMagic + 2 * sizeof(std::uint64_t);
  if (file.size() < header || std::memcmp(file.data(), kMagic, sizeof kMagic) != 0) return std::nullopt;
  std::uint64_t size = 0, checksum = 0;
  std::memcpy(&size, file.data() + sizeof kMagic, sizeof size);
  std::memcpy(&checksum, file.data() + sizeof kMagic + sizeof size, sizeof checksum);
  if (size != file.size() - header || fnv1a(file.data() + header, size) != checksum) return std::nullopt;
  return std::vector<unsigned char>(file.begin() + std::ptrdiff_t(header), file.end());
}

void ProgramBinaryStore::save(const std::string& key, const std::vector<unsigned char>& binary) const {
  if (!enabled()) return;
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  const std::filesystem::path target = file_for(key);
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path temporary =
      target.string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) return;
    const std::uint64_t size = binary.size(), checksum = fnv1a(binary.data(), binary.size());
    out.write(kMagic, sizeof kMagic);
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(reinterpret_cast<const char*>(&checksum), sizeof checksum);
    out.write(reinterpret_cast<const char*>(binary.data()), std::streamsize(binary.size()));
    if (!out) {
      out.close();
      std::filesystem::remove(temporary, error);
      return;
    }
  }
  std::filesystem::rename(temporary, target, error);  // atomic: readers see the old file or the new one
  if (error) std::filesystem::remove(temporary, error);
}

}  // namespace mbao
