// An import run in a process of its own: its result comes back whole, its
// LoadError as it was, and its crash as a LoadError naming the file and what
// it printed last, and its hang as one once its time is up.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

#include "core/error.h"
#include "scene/isolated_import.h"

namespace mbao {
namespace {

ImportedScene everything() {
  ImportedScene s;
  s.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.mesh.triangles = {{0, 1, 2}};
  s.mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 0}};
  s.masks.textures = {MaskTexture{0, 2, 1, 0, 1.0f, 0.5f, {0, 0}}};
  s.masks.texels = {0, 255};
  s.masks.triangles = {MaskedTriangle{{0, 0, 1, 0, 0, 1}, 0, 0}};
  s.masks.triangle_mask = {0};
  s.camera = Camera{{1, 2, 3}, {0, 0, 0}, {0, 1, 0}, 35.0f, {}};
  s.warnings = {"one", ""};
  s.uv_sets.loaded = true;
  s.uv_sets.sets = {{{0, 1}, {1, 1}, {0, 0}}, {{0.5f, 0.5f}, {1, 0}, {0, 1}}};
  s.uv_sets.triangle_materials = {1};
  s.uv_sets.materials = {
      MaterialUvs{"default", -1, WrapMode::Repeat, WrapMode::Repeat, std::nullopt},
      MaterialUvs{
          "floor", 1, WrapMode::ClampToEdge, WrapMode::MirroredRepeat,
          BaseColor{
              {0.5f, 0.25f, 1.0f, 0.75f}, {0x89, 'P', 'N', 'G'}, 2, WrapMode::MirroredRepeat, WrapMode::ClampToEdge}}};
  s.uv_sets.primitives = {LoadedPrimitive{2, 0, 0, 0, 3, 0, 1}};
  return s;
}

TEST(IsolatedImport, BringsTheResultBackWhole) {
  const ImportedScene s = import_isolated(everything, "file.obj", 60.0), expected = everything();
  EXPECT_EQ(s.mesh.positions, expected.mesh.positions);
  EXPECT_EQ(s.mesh.triangles, expected.mesh.triangles);
  EXPECT_EQ(s.mesh.normals, expected.mesh.normals);
  EXPECT_EQ(s.masks.texels, expected.masks.texels);
  EXPECT_EQ(s.masks.triangle_mask, expected.masks.triangle_mask);
  ASSERT_EQ(s.masks.textures.size(), 1u);
  EXPECT_EQ(s.masks.textures[0].width, 2u);
  ASSERT_EQ(s.masks.triangles.size(), 1u);
  EXPECT_EQ(s.masks.triangles[0].uv[2], 1.0f);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->eye, expected.camera->eye);
  EXPECT_EQ(s.camera->vfov_deg, 35.0f);
  EXPECT_EQ(s.warnings, expected.warnings);
  EXPECT_TRUE(s.uv_sets.loaded);
  EXPECT_EQ(s.uv_sets.sets, expected.uv_sets.sets);
  EXPECT_EQ(s.uv_sets.triangle_materials, expected.uv_sets.triangle_materials);
  ASSERT_EQ(s.uv_sets.materials.size(), 2u);
  EXPECT_EQ(s.uv_sets.materials[1].name, "floor");
  EXPECT_EQ(s.uv_sets.materials[1].occlusion_texcoord, 1);
  EXPECT_EQ(s.uv_sets.materials[1].wrap_t, WrapMode::MirroredRepeat);
  EXPECT_FALSE(s.uv_sets.materials[0].base_color.has_value());
  ASSERT_TRUE(s.uv_sets.materials[1].base_color.has_value());
  const BaseColor& color = *s.uv_sets.materials[1].base_color;
  EXPECT_EQ(color.factor, expected.uv_sets.materials[1].base_color->factor);
  EXPECT_EQ(color.image, expected.uv_sets.materials[1].base_color->image);
  EXPECT_EQ(color.texcoord, 2);
  EXPECT_EQ(color.wrap_s, WrapMode::MirroredRepeat);
  EXPECT_EQ(color.wrap_t, WrapMode::ClampToEdge);
  ASSERT_EQ(s.uv_sets.primitives.size(), 1u);
  EXPECT_EQ(s.uv_sets.primitives[0].node, 2);
  EXPECT_EQ(s.uv_sets.primitives[0].vertex_count, 3u);
}

TEST(IsolatedImport, PassesTheImportsLoadErrorOn) {
  try {
    import_isolated([]() -> ImportedScene { throw LoadError("file.obj: line 3 is bad"); }, "file.obj", 60.0);
    FAIL() << "no error";
  } catch (const LoadError& e) {
    EXPECT_STREQ(e.what(), "file.obj: line 3 is bad");
  }
}

TEST(IsolatedImport, TurnsACrashIntoALoadErrorNamingTheFile) {
  try {
    import_isolated(
        []() -> ImportedScene {
          std::fprintf(stderr, "first\nassertion failed: x > 0\n");
          std::abort();
        },
        "file.ply", 60.0);
    FAIL() << "no error";
  } catch (const LoadError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("file.ply: the importer stopped on it (signal " + std::to_string(SIGABRT), 0), 0u)
        << message;
    EXPECT_NE(message.find(": assertion failed: x > 0"), std::string::npos) << message;
    EXPECT_EQ(message.find("first"), std::string::npos) << message;
  }
}

// Whatever handlers the process has (a sanitizer's, in the sanitizer build),
// the importer's process dies of its crash, and the error names the signal.
TEST(IsolatedImport, ReportsACrashByItsSignal) {
  for (const int crash : {SIGSEGV, SIGBUS, SIGFPE}) {
    try {
      import_isolated(
          [crash]() -> ImportedScene {
            std::raise(crash);
            return {};
          },
          "file.off", 60.0);
      FAIL() << "no error for signal " << crash;
    } catch (const LoadError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("file.off: the importer stopped on it (signal " + std::to_string(crash) + ", ", 0), 0u)
          << message;
    }
  }
}

TEST(IsolatedImport, StopsAnImportThatRunsPastItsTime) {
  try {
    import_isolated(
        []() -> ImportedScene {
          for (;;) pause();  // as Assimp's PLY parser loops on some malformed headers
        },
        "file.ply", 0.2);
    FAIL() << "no error";
  } catch (const LoadError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("file.ply: the importer ran past 0.2 s on it and was stopped", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace mbao
