#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace mbao {

// OpenCL program binaries kept on disk between processes, one file per key.
// Files are written to a temporary name and renamed, so concurrent processes
// see either no file or a whole one; each carries a checksum, and a file that
// fails it (or cannot be read) counts as absent.
class ProgramBinaryStore {
 public:
  // $MBAO_CACHE_DIR if set (empty: no store), else $XDG_CACHE_HOME/mbao/kernels,
  // else ~/.cache/mbao/kernels.
  static std::filesystem::path default_directory();

  explicit ProgramBinaryStore(std::filesystem::path directory) : directory_(std::move(directory)) {}

  bool enabled() const { return !directory_.empty(); }
  std::optional<std::vector<unsigned char>> load(const std::string& key) const;
  // Best effort: a directory that cannot be written to leaves the store empty.
  void save(const std::string& key, const std::vector<unsigned char>& binary) const;

  // The file a key maps to (its name is a hash of the key).
  std::filesystem::path file_for(const std::string& key) const;

 private:
  std::filesystem::path directory_;
};

}  // namespace mbao
