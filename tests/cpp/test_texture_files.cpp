// Image paths as model files write them, found as the tools that wrote them meant (SPEC 3.2).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scene/texture_files.h"

namespace mbao {
namespace {

namespace fs = std::filesystem;

class TextureFiles : public ::testing::Test {
 protected:
  // A folder of its own: CTest runs the tests of this fixture at once, each in a process.
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("mbao_texture_files_" + std::to_string(::getpid()));
    fs::create_directories(folder_ / "maps");
    std::ofstream(folder_ / "beside.png") << "x";
    std::ofstream(folder_ / "maps" / "in_maps.png") << "x";
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
};

TEST_F(TextureFiles, RelativePathsAreTheModelFoldersWhateverTheSeparator) {
  EXPECT_EQ(find_texture_file(folder_, "maps/in_maps.png"), folder_ / "maps" / "in_maps.png");
  EXPECT_EQ(find_texture_file(folder_, "maps\\in_maps.png"), folder_ / "maps" / "in_maps.png");
  EXPECT_EQ(find_texture_file(folder_, "//maps/in_maps.png"), folder_ / "maps" / "in_maps.png");
}

TEST_F(TextureFiles, APathFromAnotherMachineIsItsFileNameBesideTheModel) {
  EXPECT_EQ(find_texture_file(folder_, "Q:\\ASSIMP\\models\\beside.png"), folder_ / "beside.png");
  EXPECT_EQ(find_texture_file(folder_, "/home/artist/beside.png"), folder_ / "beside.png");
  EXPECT_EQ(find_texture_file(folder_, "elsewhere/beside.png"), folder_ / "beside.png");
}

TEST_F(TextureFiles, AnAbsolutePathThatExistsIsTaken) {
  EXPECT_EQ(find_texture_file(fs::temp_directory_path(), (folder_ / "maps" / "in_maps.png").string()),
            folder_ / "maps" / "in_maps.png");
}

TEST_F(TextureFiles, AFileThatIsNowhereIsNamedWhereItWasFirstLookedFor) {
  EXPECT_EQ(find_texture_file(folder_, "maps/gone.png"), folder_ / "maps" / "gone.png");
  EXPECT_EQ(find_texture_file(folder_, "C:\\gone.png"), fs::path("C:/gone.png"));
}

TEST(CannotHoldAlpha, OnlyJpegIsKnownWithoutOpeningIt) {
  EXPECT_TRUE(cannot_hold_alpha("C:\\maps\\Wood.JPG"));
  EXPECT_TRUE(cannot_hold_alpha("a.jpeg"));
  EXPECT_FALSE(cannot_hold_alpha("a.png"));
  EXPECT_FALSE(cannot_hold_alpha("a.tga"));
  EXPECT_FALSE(cannot_hold_alpha("no_extension"));
}

}  // namespace
}  // namespace mbao
