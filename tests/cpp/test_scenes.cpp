#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "scene/cornell_box.h"
#include "scene/gltf_loader.h"

namespace mbao {
namespace {

const std::string kTestData = MBAO_TEST_DATA;

TEST(CornellBox, HasThePublishedGeometryAndCamera) {
  const auto scene = cornell_box();
  EXPECT_EQ(scene->mesh().triangles.size(), 32u);
  EXPECT_FALSE(scene->mesh().has_normals());
  EXPECT_EQ(scene->bounds().lo, glm::vec3(0.0f));
  EXPECT_EQ(scene->bounds().hi, glm::vec3(556.0f, 548.8f, 559.2f));
  ASSERT_TRUE(scene->camera().has_value());
  EXPECT_EQ(scene->camera()->eye, glm::vec3(278, 273, -800));
  EXPECT_EQ(scene->camera()->target, glm::vec3(278, 273, 0));
  EXPECT_EQ(scene->camera()->vfov_deg, 39.3077f);
}

// tests/data/cornell_box.glb is shared/scenes/cornell_box/scene.glb (tests/test_scenes_shared.py checks).
TEST(CornellBox, EqualsTheSharedGlbTriangleForTriangle) {
  const std::string path = kTestData + "/cornell_box.glb";
  const auto built_in = cornell_box();
  const auto loaded = load_gltf(path);
  ASSERT_EQ(loaded->mesh().positions, built_in->mesh().positions);
  ASSERT_EQ(loaded->mesh().triangles, built_in->mesh().triangles);
  EXPECT_FALSE(loaded->mesh().has_normals());
}

TEST(Scene, RejectsMeshesItCannotRender) {
  TriangleMesh empty;
  EXPECT_THROW(Scene(empty, "empty"), std::invalid_argument);
  TriangleMesh out_of_range;
  out_of_range.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  out_of_range.triangles = {{0, 1, 3}};
  try {
    Scene(out_of_range, "m");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 0 uses vertex 3"), std::string::npos) << e.what();
  }
}

TEST(Scene, BuildsItsTreeOnceAndSharesIt) {
  const auto scene = cornell_box();
  EXPECT_FALSE(scene->has_kd_tree());
  const auto first = scene->kd_tree();
  EXPECT_TRUE(scene->has_kd_tree());
  EXPECT_EQ(scene->kd_tree(), first);
}

TEST(GltfLoader, MissingAndForeignFilesRaiseLoadErrorsNamingThem) {
  try {
    load_gltf("/nonexistent/scene.glb");
    FAIL();
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.glb"), std::string::npos);
  }
  const std::string text = testing::TempDir() + "not_gltf.gltf";
  std::ofstream(text) << "this is not json";
  EXPECT_THROW(load_gltf(text), LoadError);
}

}  // namespace
}  // namespace mbao
