#include "scene/texture_files.h"

#include <algorithm>
#include <cctype>
#include <system_error>

namespace mbao {
namespace {

bool is_file(const std::filesystem::path& path) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error);
}

bool has_drive_letter(const std::string& path) {
  return path.size() >= 2 && std::isalpha(static_cast<unsigned char>(path[0])) && path[1] == ':';
}

}  // namespace

std::filesystem::path find_texture_file(const std::filesystem::path& model_folder, const std::string& reference) {
  std::string path = reference;
  std::replace(path.begin(), path.end(), '\\', '/');
  if (path.rfind("//", 0) == 0) path.erase(0, 2);
  const std::filesystem::path as_given = has_drive_letter(path) ? std::filesystem::path(path) : model_folder / path;
  if (!has_drive_letter(path) && is_file(as_given)) return as_given;
  const std::filesystem::path beside = model_folder / std::filesystem::path(path).filename();
  return is_file(beside) ? beside : as_given;
}

bool cannot_hold_alpha(const std::string& reference) {
  std::string extension = std::filesystem::path(reference).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return extension == ".jpg" || extension == ".jpeg" || extension == ".jfif";
}

}  // namespace mbao
