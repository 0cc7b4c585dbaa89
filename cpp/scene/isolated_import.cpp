#include "scene/isolated_import.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <sstream>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <type_traits>

#include "core/error.h"

namespace mbao {
namespace {

// The result as bytes: vectors of trivially copyable items as a count and their bytes.
class Writer {
 public:
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void items(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(std::uint64_t(v.size()));
    if (!v.empty()) bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s) { items(std::vector<char>(s.begin(), s.end())); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  template <typename T>
  T value() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <typename T>
  std::vector<T> items() {
    const auto count = value<std::uint64_t>();
    if (count > (bytes_.size() - at_) / sizeof(T)) broken();
    std::vector<T> v(count);
    take(v.data(), count * sizeof(T));
    return v;
  }
  std::string text() {
    const std::vector<char> chars = items<char>();
    return {chars.begin(), chars.end()};
  }

 private:
  void take(void* out, std::size_t size) {
    if (size == 0) return;  // an empty vector's data() may be null
    if (size > bytes_.size() - at_) broken();
    std::memcpy(out, bytes_.data() + at_, size);
    at_ += size;
  }
  [[noreturn]] void broken() const { throw LoadError(path_ + ": the importer's process sent back a broken result"); }

  const std::string& bytes_;
  const std::string& path_;
  std::size_t at_ = 0;
};

enum class Outcome : std::uint8_t { Scene, Error };

std::string serialized(const ImportedScene& s) {
  Writer w;
  w.value(Outcome::Scene);
  w.items(s.mesh.positions);
  w.items(s.mesh.triangles);
  w.items(s.mesh.normals);
  w.items(s.masks.textures);
  w.items(s.masks.texels);
  w.items(s.masks.triangles);
  w.items(s.masks.triangle_mask);
  w.value(s.camera.has_value());
  if (s.camera) {
    w.value(s.camera->eye);
    w.value(s.camera->target);
    w.value(s.camera->up);
    w.value(s.camera->vfov_deg);
  }
  w.value(std::uint64_t(s.warnings.size()));
  for (const std::string& warning : s.warnings) w.text(warning);
  w.value(s.uv_sets.loaded);
  w.value(std::uint64_t(s.uv_sets.sets.size()));
  for (const std::vector<glm::vec2>& set : s.uv_sets.sets) w.items(set);
  w.items(s.uv_sets.triangle_materials);
  w.value(std::uint64_t(s.uv_sets.materials.size()));
  for (const MaterialUvs& m : s.uv_sets.materials) {
    w.text(m.name);
    w.value(m.occlusion_texcoord);
    w.value(m.wrap_s);
    w.value(m.wrap_t);
    w.value(m.base_color.has_value());
    if (m.base_color) {
      w.value(m.base_color->factor);
      w.items(m.base_color->image);
      w.value(m.base_color->texcoord);
      w.value(m.base_color->wrap_s);
      w.value(m.base_color->wrap_t);
    }
  }
  w.items(s.uv_sets.primitives);
  return w.bytes();
}

ImportedScene deserialized(Reader& r) {
  ImportedScene s;
  s.mesh.positions = r.items<glm::vec3>();
  s.mesh.triangles = r.items<glm::uvec3>();
  s.mesh.normals = r.items<glm::vec3>();
  s.masks.textures = r.items<MaskTexture>();
  s.masks.texels = r.items<std::uint8_t>();
  s.masks.triangles = r.items<MaskedTriangle>();
  s.masks.triangle_mask = r.items<std::uint32_t>();
  if (r.value<bool>()) {
    Camera c;
    c.eye = r.value<glm::vec3>();
    c.target = r.value<glm::vec3>();
    c.up = r.value<glm::vec3>();
    c.vfov_deg = r.value<float>();
    s.camera = c;
  }
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) s.warnings.push_back(r.text());
  s.uv_sets.loaded = r.value<bool>();
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) s.uv_sets.sets.push_back(r.items<glm::vec2>());
  s.uv_sets.triangle_materials = r.items<std::int32_t>();
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) {
    MaterialUvs m;
    m.name = r.text();
    m.occlusion_texcoord = r.value<int>();
    m.wrap_s = r.value<WrapMode>();
    m.wrap_t = r.value<WrapMode>();
    if (r.value<bool>()) {
      BaseColor& c = m.base_color.emplace();
      c.factor = r.value<std::array<float, 4>>();
      c.image = r.items<unsigned char>();
      c.texcoord = r.value<int>();
      c.wrap_s = r.value<WrapMode>();
      c.wrap_t = r.value<WrapMode>();
    }
    s.uv_sets.materials.push_back(std::move(m));
  }
  s.uv_sets.primitives = r.items<LoadedPrimitive>();
  return s;
}

// What the child sends: the scene, or the error that stopped the import.
std::string child_result(const std::function<ImportedScene()>& import, const std::string& path) {
  Writer w;
  w.value(Outcome::Error);
  try {
    return serialized(import());
  } catch (const LoadError& e) {
    w.text(e.what());
  } catch (const std::exception& e) {
    w.text(path + ": " + e.what());
  }
  return w.bytes();
}

void write_all(int fd, const std::string& bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent stopped reading: it reports the child's end
    done += std::size_t(n);
  }
}

// Everything the child writes, until it closes its end; nullopt past `deadline`.
std::optional<std::string> read_all(int fd, std::chrono::steady_clock::time_point deadline) {
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd ready{fd, POLLIN, 0};
    const int polled = left.count() > 0 ? poll(&ready, 1, int(std::min<long long>(left.count(), 1 << 30))) : 0;
    if (polled < 0 && errno == EINTR) continue;
    if (polled == 0) return std::nullopt;
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return bytes;
    bytes.append(buffer, std::size_t(n));
  }
}

// In the child: a crash ends it at once, by its signal, which the parent
// reports. Handlers the process had would otherwise run first: a sanitizer's
// or a fuzzer's report of a crash in an uninstrumented library (and a
// fuzzer's file of the input, for a crash that the parent handles), Python's
// faulthandler's traceback.
void die_of_crashes() {
  for (const int crash : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) signal(crash, SIG_DFL);
}

// ": " and the last line the child printed, or nothing.
std::string last_line(std::FILE* printed) {
  if (!printed) return {};
  std::rewind(printed);
  std::string text;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, printed)) > 0;) text.append(buffer, n);
  const std::size_t end = text.find_last_not_of(" \t\r\n");
  if (end == std::string::npos) return {};
  const std::size_t newline = text.find_last_of('\n', end);
  const std::size_t first = newline == std::string::npos ? 0 : newline + 1;
  return ": " + text.substr(first, end + 1 - first);
}

}  // namespace

ImportedScene import_isolated(const std::function<ImportedScene()>& import, const std::string& path, double seconds) {
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
  int ends[2];
  if (pipe(ends) != 0) throw LoadError(path + ": cannot make a pipe to the importer (" + std::strerror(errno) + ")");
  // What the importer prints (an assertion's message) goes here, for the error, not to the user's terminal.
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> printed(std::tmpfile(), &std::fclose);
  std::fflush(stderr);
  const pid_t child = fork();
  if (child < 0) {
    close(ends[0]);
    close(ends[1]);
    throw LoadError(path + ": cannot start the importer's process (" + std::strerror(errno) + ")");
  }
  if (child == 0) {
    die_of_crashes();
    close(ends[0]);
    if (printed) dup2(fileno(printed.get()), STDERR_FILENO);
    write_all(ends[1], child_result(import, path));
    _exit(0);  // no exit handlers: they belong to the parent
  }
  close(ends[1]);
  const std::optional<std::string> result = read_all(ends[0], deadline);
  close(ends[0]);
  if (!result) kill(child, SIGKILL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!result) {
    std::ostringstream limit;
    limit << seconds;
    throw LoadError(path + ": the importer ran past " + limit.str() +
                    " s on it and was stopped: the file is "
                    "malformed, or too large for that time");
  }
  const std::string& bytes = *result;
  if (WIFSIGNALED(status))
    throw LoadError(path + ": the importer stopped on it (signal " + std::to_string(WTERMSIG(status)) + ", " +
                    strsignal(WTERMSIG(status)) + "): the file is malformed, or more than Assimp can read" +
                    last_line(printed.get()));
  Reader r(bytes, path);
  if (r.value<Outcome>() == Outcome::Error) throw LoadError(r.text());
  return deserialized(r);
}

}  // namespace mbao
