#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/render_settings.h"

namespace mbao {
namespace {

// The message of the std::invalid_argument that validate() throws, or "".
std::string complaint(const RenderSettings& s) {
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(RenderSettings, DefaultsAreTheSeedPapersConfiguration) {
  const RenderSettings s;
  EXPECT_EQ(complaint(s), "");
  EXPECT_EQ(s.width, 512);
  EXPECT_EQ(s.height, 512);
  EXPECT_EQ(s.samples, 4);
  EXPECT_EQ(s.bounces, 1);
  EXPECT_EQ(s.estimator, Estimator::Branching);
  EXPECT_EQ(s.organisation, KernelOrganisation::Auto);
  EXPECT_EQ(s.rho, 1.0f);
  EXPECT_FALSE(s.max_distance.has_value());  // the camera's, else inf
  EXPECT_TRUE(std::isinf(s.radius()));
}

TEST(RenderSettings, EachBadValueIsNamedWithItsRange) {
  const auto with = [](auto change) {
    RenderSettings s;
    change(s);
    return complaint(s);
  };
  EXPECT_NE(with([](RenderSettings& s) { s.width = 0; }).find("width must be in [1, 16384], got 0"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.height = -3; }).find("height"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.bounces = 0; }).find("bounces must be in [1, 16]"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.samples = 0; }).find("samples"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.spp = 0; }).find("spp"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.rho = 1.5f; }).find("rho must be in [0, 1]"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.rho = std::nanf(""); }).find("rho"), std::string::npos);
  EXPECT_NE(with([](RenderSettings& s) { s.max_distance = 0.0f; }).find("max_distance must be > 0"), std::string::npos);
}

TEST(RenderSettings, PathAllowsMoreBouncesThanBranching) {
  RenderSettings s;
  s.bounces = 40;
  EXPECT_NE(complaint(s), "");
  s.estimator = Estimator::Path;
  EXPECT_EQ(complaint(s), "");
}

TEST(RenderSettings, CountsRaysPerCameraSample) {
  RenderSettings s;
  s.samples = 4;
  s.bounces = 2;
  EXPECT_EQ(s.max_rays_per_camera_sample(), 4u + 16u);  // the paper's 20 rays per pixel
  s.estimator = Estimator::Path;
  EXPECT_EQ(s.max_rays_per_camera_sample(), 8u);
}

TEST(RenderSettings, ExplodingBranchingWorkIsRefusedWithTheRayCountAndTheAlternative) {
  RenderSettings s;
  s.samples = 64;
  s.bounces = 6;  // 64^6 > 2^32 rays per pixel
  const std::string message = complaint(s);
  EXPECT_NE(message.find("rays per pixel"), std::string::npos) << message;
  EXPECT_NE(message.find("path estimator"), std::string::npos) << message;
}

TEST(RenderSettings, CountsTheWavefrontQueuesOfTheTwoDeepestBounces) {
  RenderSettings s;
  s.samples = 4;
  EXPECT_EQ(s.max_queue_entries_per_camera_sample(), 0u);  // one bounce: nothing bounces on
  s.bounces = 2;
  EXPECT_EQ(s.max_queue_entries_per_camera_sample(), 4u);
  s.bounces = 4;
  EXPECT_EQ(s.max_queue_entries_per_camera_sample(), 64u + 16u);
}

TEST(RenderSettings, TheWavefrontRefusesThePathEstimatorAndQueuesPastItsLimit) {
  RenderSettings s;
  s.organisation = KernelOrganisation::Wavefront;
  s.bounces = 3;
  EXPECT_EQ(complaint(s), "");
  s.estimator = Estimator::Path;
  EXPECT_NE(complaint(s).find("branching estimator only"), std::string::npos) << complaint(s);
  s.estimator = Estimator::Branching;
  s.width = s.height = 1;  // one pixel: below the limit on rays in total
  s.samples = 128;
  s.bounces = 4;  // 128^3 + 128^2 queued surfaces per pixel, but only 128 + ... + 128^4 < 2^32 rays
  EXPECT_NE(complaint(s).find("surfaces per pixel"), std::string::npos) << complaint(s);
  EXPECT_FALSE(s.wavefront_can_run());
  s.organisation = KernelOrganisation::Megakernel;
  EXPECT_EQ(complaint(s), "");
}

TEST(RenderSettings, TheWavefrontCanRunTheRayTracedBranchingEstimatorWithinItsQueues) {
  RenderSettings s;
  s.bounces = 3;
  EXPECT_TRUE(s.wavefront_can_run());
  s.estimator = Estimator::Path;
  EXPECT_FALSE(s.wavefront_can_run());
  s.estimator = Estimator::Branching;
  s.method = Method::Hbao;
  EXPECT_FALSE(s.wavefront_can_run());
  s.method = Method::RayTraced;
  s.spp = std::int64_t(kMaxWavefrontQueueEntries / s.max_queue_entries_per_camera_sample());
  EXPECT_TRUE(s.wavefront_can_run());
  s.spp += 1;
  EXPECT_FALSE(s.wavefront_can_run());
}

TEST(RenderSettings, RaysInTotalAreBoundedByMaxRays) {
  RenderSettings s;
  s.width = 10;
  s.height = 20;
  s.spp = 3;
  s.samples = 4;
  s.bounces = 3;
  EXPECT_EQ(s.max_rays_in_total(), 10u * 20u * 3u * (1u + 4u + 16u + 64u));
  s.max_rays = s.max_rays_in_total();
  EXPECT_EQ(complaint(s), "");
  s.max_rays -= 1;
  EXPECT_NE(complaint(s).find("would trace up to 51000 rays"), std::string::npos) << complaint(s);
  EXPECT_NE(complaint(s).find("samples * bounces = 12"), std::string::npos) << complaint(s);
  s.estimator = Estimator::Path;
  EXPECT_EQ(s.max_rays_in_total(), 10u * 20u * 3u * (1u + 12u));
  EXPECT_EQ(complaint(s), "");
}

// Lanes walk a bounce's rays together: only the wavefront has them together.
TEST(RenderSettings, LanesAreRefusedWhereTheWavefrontCannotRunTheSettings) {
  RenderSettings s;
  s.traversal = Traversal::Lanes;
  EXPECT_EQ(complaint(s), "");
  s.organisation = KernelOrganisation::Megakernel;
  EXPECT_NE(complaint(s).find("traversal \"lanes\" walks a bounce's rays together"), std::string::npos) << complaint(s);
  s.organisation = KernelOrganisation::Auto;
  s.estimator = Estimator::Path;
  EXPECT_NE(complaint(s).find("the path estimator needs another traversal"), std::string::npos) << complaint(s);
  s.estimator = Estimator::Branching;
  s.origin_paths = true;
  EXPECT_NE(complaint(s).find("starts every ray at the root"), std::string::npos) << complaint(s);
  s.origin_paths = false;
  EXPECT_EQ(complaint(s), "");
  s.samples = 64;
  s.bounces = 5;
  s.max_rays = std::numeric_limits<std::uint64_t>::max();
  EXPECT_NE(complaint(s).find("more than its limit"), std::string::npos) << complaint(s);
}

TEST(RenderSettings, NamesParseAndPrintBothWays) {
  for (const char* name : {"branching", "path"}) EXPECT_EQ(to_string(parse_estimator(name)), name);
  for (const char* name : {"shading", "geometric"}) EXPECT_EQ(to_string(parse_normal_mode(name)), name);
  for (const char* name : {"pushdown", "restart", "short-stack", "stack", "lanes"})
    EXPECT_EQ(to_string(parse_traversal(name)), name);
  for (const char* name : {"auto", "megakernel", "wavefront"}) EXPECT_EQ(to_string(parse_organisation(name)), name);
  EXPECT_THROW(parse_estimator("Branching"), std::invalid_argument);
  EXPECT_THROW(parse_traversal("short_stack"), std::invalid_argument);
}

}  // namespace
}  // namespace mbao
