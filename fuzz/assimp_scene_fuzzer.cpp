// libFuzzer target: mbao's reading of an imported scene, in-process. The input
// drives the building of an aiScene as Assimp's aiProcess_ValidateDataStructure
// lets one through (indices in range, faces of 1-3 corners sorted by primitive
// type, at least one material), with any float bits in its positions, normals,
// UVs, transforms and cameras, embedded images of any bytes, and materials whose
// textures name embedded images, a file beside it, a missing file or any string.
// scene_from_assimp reads it, and a Scene is built from what it read, as
// load_with_assimp does. Assimp's own parsing is fuzzed apart, through the
// isolated importer (assimp_loader_fuzzer.cpp): that costs a process per input.
//
// A LoadError (mbao::Error) or std::invalid_argument is mbao's answer to bad
// input; any other exception escaping, a crash, a sanitizer report, a hang or
// running out of memory is a finding.
#include <fuzzer/FuzzedDataProvider.h>

#include <assimp/material.h>
#include <assimp/scene.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/assimp_scene.h"
#include "scene/scene.h"

namespace {

// Sizes small enough that an input builds its scene in well under a millisecond.
constexpr unsigned kMaxMeshes = 4, kMaxVertices = 48, kMaxFaces = 64, kMaxNodes = 8, kMaxMaterials = 3, kMaxCameras = 2,
                   kMaxTextureSide = 8, kMaxEncodedImage = 512;

float any_float(FuzzedDataProvider& in) {
  const auto bits = in.ConsumeIntegral<std::uint32_t>();
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

aiVector3D any_vector(FuzzedDataProvider& in) {
  const float x = any_float(in), y = any_float(in);
  return {x, y, any_float(in)};
}

// Names a texture may have: embedded images by index and by file name, the
// image beside the "file" (MBAO_FUZZ_BASE_DIR/mask.png), a missing one, and any string.
aiString texture_name(FuzzedDataProvider& in) {
  static const char* const kNames[] = {
      "*0", "*1", "*7", "embedded.png", "mask.png", "missing.png", "C:\\x\\mask.png", "//mask.png"};
  if (in.ConsumeBool()) return aiString(in.ConsumeRandomLengthString(32));
  return aiString(kNames[in.ConsumeIntegralInRange<std::size_t>(0, std::size(kNames) - 1)]);
}

aiTexture* embedded_texture(FuzzedDataProvider& in) {
  auto* t = new aiTexture;
  t->mFilename = aiString("embedded.png");
  if (in.ConsumeBool()) {  // compressed: mWidth bytes of an encoded image in pcData
    const std::vector<std::uint8_t> bytes =
        in.ConsumeBytes<std::uint8_t>(in.ConsumeIntegralInRange(0u, kMaxEncodedImage));
    const std::size_t texels = (bytes.size() + sizeof(aiTexel) - 1) / sizeof(aiTexel);
    t->pcData = new aiTexel[texels > 0 ? texels : 1];
    if (!bytes.empty()) std::memcpy(t->pcData, bytes.data(), bytes.size());
    t->mWidth = unsigned(bytes.size());
    t->mHeight = 0;
    std::strcpy(t->achFormatHint, in.ConsumeBool() ? "png" : "jpg");
  } else {
    t->mWidth = in.ConsumeIntegralInRange(1u, kMaxTextureSide);
    t->mHeight = in.ConsumeIntegralInRange(1u, kMaxTextureSide);
    t->pcData = new aiTexel[t->mWidth * t->mHeight];
    for (unsigned i = 0; i < t->mWidth * t->mHeight; ++i)
      t->pcData[i] = aiTexel{0, 0, 0, in.ConsumeIntegral<std::uint8_t>()};
    std::strcpy(t->achFormatHint, "argb8888");
  }
  return t;
}

aiMaterial* material(FuzzedDataProvider& in) {
  auto* m = new aiMaterial;
  const aiString name(in.ConsumeRandomLengthString(16));
  m->AddProperty(&name, AI_MATKEY_NAME);
  if (in.ConsumeBool()) {
    const float opacity = any_float(in);
    m->AddProperty(&opacity, 1, AI_MATKEY_OPACITY);
  }
  if (in.ConsumeBool()) {
    const aiColor4D color(any_float(in), any_float(in), any_float(in), any_float(in));
    if (in.ConsumeBool())
      m->AddProperty(&color, 1, AI_MATKEY_BASE_COLOR);
    else
      m->AddProperty(&color, 1, AI_MATKEY_COLOR_DIFFUSE);
  }
  for (const aiTextureType type :
       {aiTextureType_OPACITY, aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR, aiTextureType_AMBIENT_OCCLUSION}) {
    if (!in.ConsumeBool()) continue;
    const aiString file = texture_name(in);
    m->AddProperty(&file, AI_MATKEY_TEXTURE(type, 0));
    const int channel = in.ConsumeIntegralInRange(-1, 9);
    m->AddProperty(&channel, 1, AI_MATKEY_UVWSRC(type, 0));
    const int modes[2] = {in.ConsumeIntegralInRange(0, 4), in.ConsumeIntegralInRange(0, 4)};
    m->AddProperty(&modes[0], 1, AI_MATKEY_MAPPINGMODE_U(type, 0));
    m->AddProperty(&modes[1], 1, AI_MATKEY_MAPPINGMODE_V(type, 0));
  }
  return m;
}

aiMesh* mesh(FuzzedDataProvider& in, unsigned materials) {
  auto* m = new aiMesh;
  m->mName = aiString(in.ConsumeRandomLengthString(16));
  m->mMaterialIndex = in.ConsumeIntegralInRange(0u, materials - 1);
  m->mNumVertices = in.ConsumeIntegralInRange(1u, kMaxVertices);
  m->mVertices = new aiVector3D[m->mNumVertices];
  for (unsigned v = 0; v < m->mNumVertices; ++v) m->mVertices[v] = any_vector(in);
  if (in.ConsumeBool()) {
    m->mNormals = new aiVector3D[m->mNumVertices];
    for (unsigned v = 0; v < m->mNumVertices; ++v) m->mNormals[v] = any_vector(in);
  }
  const auto channels = in.ConsumeIntegral<std::uint8_t>();
  for (unsigned c = 0; c < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++c) {
    if (!(channels & (1u << c))) continue;
    m->mNumUVComponents[c] = 2;
    m->mTextureCoords[c] = new aiVector3D[m->mNumVertices];
    for (unsigned v = 0; v < m->mNumVertices; ++v)
      m->mTextureCoords[c][v] = aiVector3D(any_float(in), any_float(in), 0);
  }
  // One primitive type per mesh, as aiProcess_SortByPType leaves them.
  const unsigned corners = in.ConsumeIntegralInRange(1u, 3u);
  m->mPrimitiveTypes = corners == 3   ? aiPrimitiveType_TRIANGLE
                       : corners == 2 ? aiPrimitiveType_LINE
                                      : aiPrimitiveType_POINT;
  m->mNumFaces = in.ConsumeIntegralInRange(1u, kMaxFaces);
  m->mFaces = new aiFace[m->mNumFaces];
  for (unsigned f = 0; f < m->mNumFaces; ++f) {
    m->mFaces[f].mNumIndices = corners;
    m->mFaces[f].mIndices = new unsigned[corners];
    for (unsigned k = 0; k < corners; ++k)
      m->mFaces[f].mIndices[k] = in.ConsumeIntegralInRange(0u, m->mNumVertices - 1);
  }
  return m;
}

aiMatrix4x4 transform(FuzzedDataProvider& in) {
  if (in.ConsumeBool()) return aiMatrix4x4();
  aiMatrix4x4 t;
  for (unsigned row = 0; row < 4; ++row)
    for (unsigned column = 0; column < 4; ++column) t[row][column] = any_float(in);
  return t;
}

// A tree of nodes, each a child of one made before it, naming meshes by index.
aiNode* node_tree(FuzzedDataProvider& in, unsigned meshes) {
  std::vector<aiNode*> nodes;
  std::vector<std::vector<aiNode*>> children;
  const unsigned count = in.ConsumeIntegralInRange(1u, kMaxNodes);
  for (unsigned i = 0; i < count; ++i) {
    auto* n = new aiNode("node" + std::to_string(i));
    n->mTransformation = transform(in);
    n->mNumMeshes = in.ConsumeIntegralInRange(0u, 3u);
    n->mMeshes = new unsigned[n->mNumMeshes > 0 ? n->mNumMeshes : 1];
    for (unsigned k = 0; k < n->mNumMeshes; ++k) n->mMeshes[k] = in.ConsumeIntegralInRange(0u, meshes - 1);
    if (i > 0) {
      const unsigned parent = in.ConsumeIntegralInRange(0u, i - 1);
      n->mParent = nodes[parent];
      children[parent].push_back(n);
    }
    nodes.push_back(n);
    children.emplace_back();
  }
  for (unsigned i = 0; i < count; ++i)
    if (!children[i].empty()) nodes[i]->addChildren(unsigned(children[i].size()), children[i].data());
  return nodes[0];
}

aiCamera* camera(FuzzedDataProvider& in, unsigned nodes) {
  auto* c = new aiCamera;
  c->mName = aiString("node" + std::to_string(in.ConsumeIntegralInRange(0u, nodes)));  // the last names no node
  c->mPosition = any_vector(in);
  c->mLookAt = any_vector(in);
  c->mUp = any_vector(in);
  c->mHorizontalFOV = any_float(in);
  c->mAspect = any_float(in);
  c->mOrthographicWidth = in.ConsumeBool() ? any_float(in) : 0.0f;
  return c;
}

template <typename T>
T** array_of(std::vector<T*> items) {
  T** array = new T*[items.size() > 0 ? items.size() : 1];
  std::copy(items.begin(), items.end(), array);
  return array;
}

std::unique_ptr<aiScene> scene(FuzzedDataProvider& in) {
  auto s = std::make_unique<aiScene>();
  if (in.ConsumeBool()) s->mFlags |= AI_SCENE_FLAGS_INCOMPLETE;
  std::vector<aiTexture*> textures(in.ConsumeIntegralInRange(0u, 2u));
  for (aiTexture*& t : textures) t = embedded_texture(in);
  s->mNumTextures = unsigned(textures.size());
  s->mTextures = array_of(textures);
  std::vector<aiMaterial*> materials(in.ConsumeIntegralInRange(1u, kMaxMaterials));
  for (aiMaterial*& m : materials) m = material(in);
  s->mNumMaterials = unsigned(materials.size());
  s->mMaterials = array_of(materials);
  std::vector<aiMesh*> meshes(in.ConsumeIntegralInRange(1u, kMaxMeshes));
  for (aiMesh*& m : meshes) m = mesh(in, s->mNumMaterials);
  s->mNumMeshes = unsigned(meshes.size());
  s->mMeshes = array_of(meshes);
  s->mRootNode = node_tree(in, s->mNumMeshes);
  std::vector<aiCamera*> cameras(in.ConsumeIntegralInRange(0u, kMaxCameras));
  for (aiCamera*& c : cameras) c = camera(in, kMaxNodes);
  s->mNumCameras = unsigned(cameras.size());
  s->mCameras = array_of(cameras);
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  mbao::LoadOptions options;
  options.normals = in.ConsumeBool();
  options.texcoords = in.ConsumeBool();
  options.base_colors = in.ConsumeBool();
  const std::unique_ptr<aiScene> built = scene(in);
  const std::string path = std::string(MBAO_FUZZ_BASE_DIR) + "/fuzz-input.dae";
  try {
    mbao::ImportedScene s = mbao::scene_from_assimp(*built, path, options);
    mbao::Scene(std::move(s.mesh), path, s.camera, std::move(s.warnings), std::move(s.masks), std::move(s.uv_sets));
  } catch (const mbao::Error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
