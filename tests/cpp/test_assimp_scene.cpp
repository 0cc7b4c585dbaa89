// What mbao reads from a scene Assimp has imported, for what no file here
// makes Assimp produce: a scene flagged incomplete that still has triangles.
#include <gtest/gtest.h>

#include <assimp/scene.h>

#include <memory>
#include <string>

#include "core/error.h"
#include "scene/assimp_scene.h"

namespace mbao {
namespace {

// One triangle in one mesh at the root node, without materials: as LightWave's
// scene loader leaves a scene whose objects have none, flagged incomplete.
std::unique_ptr<aiScene> triangle_without_materials() {
  auto scene = std::make_unique<aiScene>();
  scene->mFlags = AI_SCENE_FLAGS_INCOMPLETE;
  auto* mesh = new aiMesh;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = 3;
  mesh->mVertices = new aiVector3D[3]{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh->mNumFaces = 1;
  mesh->mFaces = new aiFace[1];
  mesh->mFaces[0].mNumIndices = 3;
  mesh->mFaces[0].mIndices = new unsigned[3]{0, 1, 2};
  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh* [1] { mesh };
  scene->mRootNode = new aiNode("root");
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};
  return scene;
}

TEST(AssimpScene, AnIncompleteSceneWithTrianglesLoadsThemWithAWarning) {
  const ImportedScene s = scene_from_assimp(*triangle_without_materials(), "objects.lws", LoadOptions{});
  ASSERT_EQ(s.mesh.triangles.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            "objects.lws: Assimp flagged the scene incomplete (it has no materials); its triangles "
            "are loaded");
}

TEST(AssimpScene, ASceneWithoutMeshesSaysSo) {
  std::unique_ptr<aiScene> scene = triangle_without_materials();
  delete scene->mMeshes[0];
  scene->mNumMeshes = 0;
  scene->mRootNode->mNumMeshes = 0;
  try {
    scene_from_assimp(*scene, "cameras.dae", LoadOptions{});
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    EXPECT_EQ(std::string(e.what()), "cameras.dae: no meshes in it (Assimp found no geometry it could read)");
  }
}

}  // namespace
}  // namespace mbao
