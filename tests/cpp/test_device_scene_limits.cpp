// A scene whose buffers a device cannot allocate is refused before its tree is
// built, with the buffer, its bytes, the device's limit and what would fit.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "render/device_scene.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

TEST(DeviceSceneLimits, RefusesABufferPastTheLargestAllocationBeforeTheTree) {
  const auto scene = cornell_box();  // 32 triangles: 1536 bytes of corners
  EXPECT_NO_THROW(DeviceScene::check_fits(*scene, 1536, "a device", false));
  try {
    DeviceScene::check_fits(*scene, 1024, "a device", false);
    FAIL() << "no error";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("triangles' corners need one device buffer of 1536 bytes (32 triangles), more than the 1024 bytes"), std::string::npos)
        << message;
    EXPECT_NE(message.find("that a device allocates at most (CL_DEVICE_MAX_MEM_ALLOC_SIZE): about 21 triangles fit"),
              std::string::npos)
        << message;
  }
  EXPECT_FALSE(scene->has_kd_tree());
}

}  // namespace
}  // namespace mbao
