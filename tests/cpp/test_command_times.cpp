// CommandTimes: a timed renderer's queue reports each kernel, fill and
// read-back of a frame and the device's idle time before each, and nothing is
// timed that was not asked for.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "opencl/devices.h"
#include "opencl/command_times.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"

namespace mbao {
namespace {

RenderSettings wavefront_settings() {
  RenderSettings s;
  s.width = s.height = 64;
  s.bounces = 2;
  s.organisation = KernelOrganisation::Wavefront;
  s.traversal = Traversal::Stack;
  return s;
}

TEST(CommandTimes, AFrameOfATimedRendererShowsEachOfItsCommandsWithinItsTime) {
  Renderer renderer(default_device(), QueueTiming::On);
  CommandTimes times(renderer.queue());
  const auto scene = cornell_box();
  renderer.render(scene, *scene->camera(), wavefront_settings());  // builds, uploads, launches empty grids
  times.take();
  const RenderResult result = renderer.render(scene, *scene->camera(), wavefront_settings());
  const std::vector<CommandTimes::Total> totals = times.take();

  // One tile: the camera rays; the bounce queues' lengths zeroed; the first bounce; the length of its
  // queue read back for the second; the pixels' values; then the image (AO, coverage, rays per pixel)
  // read back.
  const std::vector<std::pair<std::string, std::size_t>> expected = {
      {"trace_camera_rays", 1}, {"fill", 1}, {"wavefront_first_bounce", 1}, {"read-back", 4}, {"wavefront_bounce", 1},
      {"wavefront_finish", 1}};
  ASSERT_EQ(totals.size(), expected.size());
  double span_ms = 0.0;
  for (std::size_t i = 0; i < totals.size(); ++i) {
    EXPECT_EQ(totals[i].command, expected[i].first);
    EXPECT_EQ(totals[i].runs, expected[i].second) << totals[i].command;
    EXPECT_GT(totals[i].device_ms, 0.0) << totals[i].command;
    // An in-order queue starts a command only once the one before it has ended.
    EXPECT_GE(totals[i].idle_before_ms, 0.0) << totals[i].command;
    span_ms += totals[i].device_ms + totals[i].idle_before_ms;
  }
  // From the first command's queueing to the last one's end, all inside the frame.
  EXPECT_LE(span_ms, result.stats.frame_ms);
  EXPECT_TRUE(times.take().empty());
}

TEST(CommandTimes, OnlyTheQueueItWasMadeForIsTimedAndOnlyWhileItLives) {
  Renderer timed(default_device(), QueueTiming::On);
  EXPECT_FALSE(CommandTimes::timed(timed.queue()));
  {
    CommandTimes times(timed.queue());
    EXPECT_TRUE(CommandTimes::timed(timed.queue()));
    EXPECT_FALSE(CommandTimes::timed(Renderer::for_device(default_device()).queue()));
  }
  EXPECT_FALSE(CommandTimes::timed(timed.queue()));
}

TEST(CommandTimes, AQueueThatKeepsNoTimesIsRefusedByName) {
  try {
    CommandTimes times(Renderer::for_device(default_device()).queue());
    FAIL() << "an untimed queue was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("CL_QUEUE_PROFILING_ENABLE"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mbao
