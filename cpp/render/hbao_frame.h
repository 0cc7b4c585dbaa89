#pragma once

#include <cstddef>
#include <cstdint>

#include "opencl/opencl.h"
#include "render/device_scene.h"
#include "render/render_settings.h"
#include "scene/camera.h"

namespace mbao {

// The device side of one HBAO render (hbao.cl): a G-buffer of the camera rays'
// hits for the whole image, which HBAO reads around every pixel, then the image.
class HbaoFrame {
 public:
  HbaoFrame(const cl::Context& context, const cl::Device& device, const cl::Program& program,
            const DeviceScene& scene, const Camera& camera, const RenderSettings& settings);

  void enqueue(cl::CommandQueue& queue);
  // Copies the image back (non-blocking).
  void enqueue_read_back(cl::CommandQueue& queue, float* ao, std::uint8_t* coverage);

  std::size_t bytes() const { return device_bytes(pixels_); }
  // What a frame of this many pixels allocates: known before it does.
  static std::size_t device_bytes(std::size_t pixels);

 private:
  std::size_t pixels_;
  cl::Buffer positions_, normals_, ao_, coverage_;
  cl::Kernel gbuffer_, hbao_;
  std::size_t gbuffer_group_ = 0, hbao_group_ = 0;
};

}  // namespace mbao
