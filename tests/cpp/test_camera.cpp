#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "scene/camera.h"

namespace mbao {
namespace {

// A file holding `text` while it lives, named `name` with this process's id
// before it: CTest runs this file's tests at once, each in a process.
class TempFile {
 public:
  TempFile(const std::string& name, const std::string& text)
      : path_(testing::TempDir() + std::to_string(::getpid()) + "_" + name) {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

TEST(Camera, BasisFollowsSpec31) {
  Camera camera;
  camera.eye = {0, 0, 0};
  camera.target = {0, 0, -5};  // looking down -z as in glTF
  camera.up = {0, 2, 0};       // need not be unit or orthogonal
  camera.vfov_deg = 90.0f;
  const CameraBasis basis(camera);
  EXPECT_NEAR(glm::distance(basis.forward, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(basis.right, glm::vec3(1, 0, 0)), 0.0f, 1e-6f);  // right-handed: x to the right
  EXPECT_NEAR(glm::distance(basis.up, glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(basis.tan_half_vfov, 1.0f, 1e-6f);
}

// Float squares overflow from about 1.8e19 and underflow below about 1e-23:
// a view's frame is found all the same from 1e-30 to 3e38, and a truly
// degenerate view is still refused at those scales.
TEST(Camera, ExtremeScalesKeepTheirFrame) {
  struct View {
    glm::vec3 eye, target, up;
  };
  const View valid[] = {{{0, 0, 3e19f}, {0, 0, 0}, {0, 1, 0}},      {{0, 0, 1e-30f}, {0, 0, 0}, {0, 1, 0}},
                        {{0, 0, 5}, {0, 0, 0}, {0, 1e-30f, 0}},     {{0, 0, 5}, {0, 0, 0}, {0, 3e19f, 0}},
                        {{0, 0, 3e38f}, {0, 0, -3e38f}, {0, 1, 0}}, {{0, 0, 1e-30f}, {0, 0, -1e-30f}, {0, 1e30f, 0}}};
  for (const View& view : valid) {
    Camera camera;
    camera.eye = view.eye;
    camera.target = view.target;
    camera.up = view.up;
    EXPECT_NO_THROW(camera.validate()) << view.eye.z << " " << view.up.y;
    const CameraBasis basis(camera);
    EXPECT_NEAR(glm::distance(basis.forward, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(basis.right, glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(basis.up, glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  }
  Camera parallel;
  parallel.eye = {0, 0, 3e19f};
  parallel.target = {0, 0, 0};
  parallel.up = {0, 0, 3e19f};
  EXPECT_THROW(parallel.validate(), std::invalid_argument);
  Camera same;
  same.eye = same.target = {1e-30f, 0, 0};
  EXPECT_THROW(same.validate(), std::invalid_argument);
}

TEST(Camera, LoadsCameraJsonWithOptionalMaxDistance) {
  const Camera c = Camera::load(
      TempFile("cam.json",
               R"({"eye": [1, 2, 3], "target": [1, 2, 0], "up": [0, 1, 0], "vfov_deg": 45, "max_distance": 7.5})")
          .path());
  EXPECT_EQ(c.eye, glm::vec3(1, 2, 3));
  EXPECT_EQ(c.target, glm::vec3(1, 2, 0));
  EXPECT_EQ(c.vfov_deg, 45.0f);
  ASSERT_TRUE(c.max_distance.has_value());
  EXPECT_EQ(*c.max_distance, 7.5f);
  const Camera d = Camera::load(
      TempFile("cam2.json", R"({"eye": [1, 2, 3], "target": [1, 2, 0], "up": [0, 1, 0], "vfov_deg": 45})").path());
  EXPECT_FALSE(d.max_distance.has_value());
}

// The LoadError message for a camera file with this text, or "".
std::string load_error(const std::string& text) {
  try {
    Camera::load(TempFile("bad.json", text).path());
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

TEST(Camera, BadFilesNameTheFileAndTheField) {
  EXPECT_NE(load_error("{").find("not valid JSON"), std::string::npos);
  EXPECT_NE(load_error(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, 0]})").find("\"vfov_deg\" is missing"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"eye": [0, 0], "target": [0, 0, 0], "up": [0, 1, 0], "vfov_deg": 40})").find("\"eye\""),
            std::string::npos);
  EXPECT_NE(load_error(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "up": [0, 0, 1], "vfov_deg": 40})").find("parallel"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, 0], "vfov_deg": 180})").find("vfov_deg"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"eye": [0, 0, 1], "target": [0, 0, 0], "up": [0, 1, 0], "vfov_deg": 180})").find("bad.json"),
            std::string::npos);
  try {
    Camera::load("/nonexistent/camera.json");
    FAIL();
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/camera.json"), std::string::npos);
  }
}

TEST(Camera, FramingSeesTheWholeBox) {
  Bounds3 box;
  box.extend({-3, 1, 10});
  box.extend({5, 2, 14});
  for (float aspect : {0.25f, 1.0f, 3.0f}) {
    const Camera camera = Camera::framing(box, aspect);
    camera.validate();
    const CameraBasis basis(camera);
    const float tan_half_h = basis.tan_half_vfov * aspect;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                        (corner & 4) ? box.hi.z : box.lo.z);
      const glm::vec3 v = p - camera.eye;
      const float depth = glm::dot(v, basis.forward);
      ASSERT_GT(depth, 0.0f);
      EXPECT_LE(std::abs(glm::dot(v, basis.right)) / depth, tan_half_h * 1.0001f) << "aspect " << aspect;
      EXPECT_LE(std::abs(glm::dot(v, basis.up)) / depth, basis.tan_half_vfov * 1.0001f) << "aspect " << aspect;
    }
  }
}

}  // namespace
}  // namespace mbao
