#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "opencl/program_binary_store.h"

namespace mbao {
namespace {

std::filesystem::path fresh_directory(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / name;
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(ProgramBinaryStore, KeepsBinariesByKey) {
  const ProgramBinaryStore store(fresh_directory("store_keeps"));
  const std::vector<unsigned char> binary = {1, 2, 3, 0, 255};
  EXPECT_FALSE(store.load("key"));
  store.save("key", binary);
  ASSERT_TRUE(store.load("key"));
  EXPECT_EQ(*store.load("key"), binary);
  EXPECT_FALSE(store.load("another key"));
  EXPECT_NE(store.file_for("key"), store.file_for("kez"));
}

TEST(ProgramBinaryStore, DamagedFilesCountAsAbsent) {
  const ProgramBinaryStore store(fresh_directory("store_damaged"));
  store.save("key", std::vector<unsigned char>(100, 7));
  const std::filesystem::path file = store.file_for("key");
  const auto size = std::filesystem::file_size(file);
  std::filesystem::resize_file(file, size - 1);  // truncated
  EXPECT_FALSE(store.load("key"));
  store.save("key", std::vector<unsigned char>(100, 7));
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(size - 5));
    f.put(8);  // one byte of the binary changed
  }
  EXPECT_FALSE(store.load("key"));
}

TEST(ProgramBinaryStore, LeavesNoTemporaryFiles) {
  const std::filesystem::path dir = fresh_directory("store_tidy");
  const ProgramBinaryStore store(dir);
  for (int i = 0; i < 5; ++i) store.save("key " + std::to_string(i % 2), std::vector<unsigned char>(10, 1));
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().extension(), ".bin");
    ++files;
  }
  EXPECT_EQ(files, 2u);
}

TEST(ProgramBinaryStore, AnEmptyDirectoryTurnsItOff) {
  const ProgramBinaryStore store{std::filesystem::path()};
  EXPECT_FALSE(store.enabled());
  store.save("key", {1});
  EXPECT_FALSE(store.load("key"));
}

TEST(ProgramBinaryStore, AnUnwritableDirectoryIsNoError) {
  const ProgramBinaryStore store("/proc/no/such/place");
  store.save("key", {1});
  EXPECT_FALSE(store.load("key"));
}

}  // namespace
}  // namespace mbao
