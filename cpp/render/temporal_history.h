// What temporal accumulation (SPEC 7.4) keeps on the device from one frame of
// a sequence to the next: per pixel the accumulated value a, its variance u
// and the history length n, with the G-buffer and camera they were seen from.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "opencl/opencl.h"
#include "render/ao_kernel_args.h"
#include "render/render_settings.h"

namespace mbao {

class TemporalHistory {
 public:
  explicit TemporalHistory(const TemporalSettings& settings);

  const TemporalSettings& settings() const { return settings_; }

  // Replaces the frame's image and variance (width x height, in `frame`) by
  // their blend with the history (temporal.cl), and keeps the blend, the
  // frame's G-buffer and `camera` (in the scene's device frame) as the history
  // of the next. The first frame, or one of another size or context, starts
  // without history.
  void enqueue_accumulate(cl::CommandQueue& queue, const cl::Context& context, const cl::Program& program,
                          const FrameBuffers& frame, const CameraArgs& camera, std::size_t work_group_size);

  // Each pixel's history length n after the last frame: 0 where it missed.
  void enqueue_read_lengths(cl::CommandQueue& queue, std::vector<cl_uint>& lengths) const;

  // What the history holds on the device for `pixels` pixels, besides the G-buffer it shares with the frame.
  static std::size_t device_bytes(std::size_t pixels) { return 2 * 3 * pixels * sizeof(cl_float); }

 private:
  // Fresh buffers, and no history, where the frame differs in size or context from the last.
  void start_over_unless_like(const cl::Context& context, const CameraArgs& camera);

  TemporalSettings settings_;
  cl::Context context_;
  std::optional<CameraArgs> camera_;  // the last frame's; unset: no history
  // The last frame's blend (ao, variance, length) and the pair the next one writes.
  cl::Buffer ao_, variance_, length_, next_ao_, next_variance_, next_length_;
  cl::Buffer gbuffer_;  // the last frame's, kept from its FrameBuffers
};

}  // namespace mbao
