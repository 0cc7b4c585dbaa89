// What a scene takes on a device: a scene whose buffers a device cannot
// allocate is refused before its tree is built, with the buffer, its bytes,
// the device's limit and what would fit; and a scene is there once, whichever
// normals its renders read.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "opencl/devices.h"
#include "random_soup.h"
#include "render/device_scene.h"
#include "render/render_plan.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

TEST(DeviceSceneLimits, RefusesABufferPastTheLargestAllocationBeforeTheTree) {
  const auto scene = cornell_box();  // 32 triangles: 1536 bytes of corners
  EXPECT_NO_THROW(DeviceScene::check_fits(*scene, 1536, "a device", false, false));
  // Read from the mesh's vertices, its largest buffer is theirs: 64 of 12 bytes.
  EXPECT_NO_THROW(DeviceScene::check_fits(*scene, 768, "a device", false, true));
  try {
    DeviceScene::check_fits(*scene, 1024, "a device", false, false);
    FAIL() << "no error";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(
                  "triangles' corners need one device buffer of 1536 bytes (32 triangles), more than the 1024 bytes"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("that a device allocates at most (CL_DEVICE_MAX_MEM_ALLOC_SIZE): about 21 triangles fit"),
              std::string::npos)
        << message;
  }
  EXPECT_FALSE(scene->has_kd_tree());
}

TEST(DeviceSceneLimits, ATreePastTheLargestAllocationStopsItsBuild) {
  const auto scene = std::make_shared<const Scene>(random_soup(40000, 5), "soup");
  try {
    DeviceScene::tree_within(*scene, 64 * 1024, "a device");
    FAIL() << "no error";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("soup: its kd-tree's nodes need one device buffer of more than "), std::string::npos)
        << message;
    EXPECT_NE(message.find("(40000 triangles; the build stopped there), more than the 65536 bytes that a device "
                           "allocates at most"),
              std::string::npos)
        << message;
  }
  EXPECT_FALSE(scene->has_kd_tree());
  const std::size_t bytes = DeviceScene::tree_within(*scene, std::size_t(1) << 30, "a device")->stats.memory_bytes;
  EXPECT_GT(bytes, 64u * 1024u);
  EXPECT_TRUE(scene->has_kd_tree());
}

// A render with shading normals and a trace without them read one copy of
// the scene: the second upload adds or leaves out the normals alone.
TEST(DeviceSceneCache, TheTwoChoicesOfNormalsShareTheRestOfTheScene) {
  TriangleMesh mesh = random_soup(500, 3);
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
  const auto scene = std::make_shared<const Scene>(std::move(mesh), "soup with normals");
  ComputeContext compute(default_device());
  DeviceSceneCache scenes;
  const bool indexed = plans_indexed_triangles(compute.device(), scene->mesh().triangles.size());
  const std::shared_ptr<const DeviceScene> with = scenes.get(compute, scene, true, indexed);
  const std::shared_ptr<const DeviceScene> without = scenes.get(compute, scene, false, indexed);
  EXPECT_NE(with, without);
  EXPECT_EQ(scenes.get(compute, scene, true, indexed), with);
  EXPECT_TRUE(with->shares_geometry_with(*without));
  // The normals, and the triangles' vertex ids where the device does not read the mesh's own.
  const std::size_t normal_bytes = (indexed ? 0 : scene->mesh().triangles.size() * 3 * sizeof(cl_uint)) +
                                   scene->mesh().normals.size() * sizeof(cl_float4);
  EXPECT_EQ(with->bytes(), without->bytes() + normal_bytes);
  // Another scene's upload shares nothing with it.
  EXPECT_FALSE(scenes.get(compute, cornell_box(), true, false)->shares_geometry_with(*with));
}

}  // namespace
}  // namespace mbao
