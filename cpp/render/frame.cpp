#include "render/frame.h"

#include <stdexcept>

#include "mbao/gbuffer.h"
#include "opencl/launch.h"

namespace mbao {

namespace {

std::size_t camera_hit_bytes(const RenderSettings& s, std::size_t tile_pixels) {
  return tile_pixels * std::size_t(s.spp) * sizeof(cl_uint4);
}

}  // namespace

Frame::BufferSizes Frame::buffer_sizes(const RenderSettings& s, const RenderPlan& plan, std::size_t tile_pixels,
                                       PrimarySurfaces primaries) {
  const std::size_t pixels = std::size_t(s.width) * std::size_t(s.height);
  const bool ao = plan.output == FrameOutput::AmbientOcclusion;
  const bool image = plan.output != FrameOutput::GBuffer;  // a G-buffer frame's image is its planes
  BufferSizes sizes;
  sizes.camera_hits = ao ? camera_hit_bytes(s, tile_pixels) : 0;
  sizes.ao = image ? pixels * sizeof(cl_float) : 0;
  sizes.coverage = image ? pixels * sizeof(cl_uchar) : 0;
  sizes.secondary_rays = ao ? pixels * sizeof(cl_uint) : 0;
  sizes.ao_second_moment = primaries == PrimarySurfaces::GivenPoints ? pixels * sizeof(cl_float) : 0;
  sizes.ao_variance = ao && (s.variance || s.filtered()) ? pixels * sizeof(cl_float) : 0;
  sizes.gbuffer = pixels * gbuffer_plane_count(plan.gbuffer_planes) * sizeof(cl_float);
  sizes.traversal_totals = s.traversal_stats ? 4 * sizeof(cl_ulong) : 0;
  sizes.wavefront = plan.kernels.wavefront() ? Wavefront::device_bytes(s, plan.kernels, tile_pixels) : 0;
  return sizes;
}

std::size_t Frame::device_bytes(const RenderSettings& s, const RenderPlan& plan, std::size_t tile_pixels,
                                PrimarySurfaces primaries) {
  return buffer_sizes(s, plan, tile_pixels, primaries).total();
}

Frame::Frame(const cl::Context& context, const cl::Device& device, const cl::Program& program, const DeviceScene& scene,
             const Camera& camera, const RenderSettings& s, const RenderPlan& plan, std::size_t tile_pixels,
             PrimarySurfaces primaries)
    : scene_(scene),
      camera_args_(camera, s),
      ao_args_(camera, s, primaries),
      seed_(seed_words(s.seed)),
      pixels_(std::size_t(s.width) * std::size_t(s.height)),
      tile_pixels_(tile_pixels),
      spp_(std::size_t(s.spp)),
      camera_rays_per_item_(plan.kernels.camera_samples_per_item),
      gbuffer_planes_(plan.gbuffer_planes) {
  const BufferSizes sizes = buffer_sizes(s, plan, tile_pixels, primaries);
  const auto allocate = [&](cl_mem_flags flags, std::size_t bytes) {
    return bytes ? cl::Buffer(context, flags, bytes) : cl::Buffer();
  };
  buffers_.camera_hits = allocate(CL_MEM_READ_WRITE, sizes.camera_hits);
  buffers_.ao = allocate(CL_MEM_WRITE_ONLY, sizes.ao);
  buffers_.coverage = allocate(CL_MEM_WRITE_ONLY, sizes.coverage);
  buffers_.secondary_rays = allocate(CL_MEM_WRITE_ONLY, sizes.secondary_rays);
  buffers_.ao_second_moment = allocate(CL_MEM_WRITE_ONLY, sizes.ao_second_moment);
  buffers_.ao_variance = allocate(CL_MEM_READ_WRITE, sizes.ao_variance);
  buffers_.gbuffer = allocate(CL_MEM_READ_WRITE, sizes.gbuffer);
  if (sizes.traversal_totals) {
    const cl_ulong zeros[4] = {0, 0, 0, 0};
    buffers_.traversal_totals =
        cl::Buffer(context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof zeros, const_cast<cl_ulong*>(zeros));
  }
  bytes_ = sizes.total();

  camera_rays_ = cl::Kernel(program, plan.kernels.camera_rays.c_str());
  camera_group_ = work_group_size_for(camera_rays_, device, s.work_group_size);

  if (plan.kernels.ao == AoLaunches::Megakernel) {
    ao_kernel_ = cl::Kernel(program, plan.kernels.megakernel.c_str());
    ao_group_ = work_group_size_for(ao_kernel_, device, s.work_group_size);
  } else if (plan.kernels.wavefront()) {
    wavefront_ =
        std::make_unique<Wavefront>(context, device, program, scene, ao_args_, s, plan.kernels, tile_pixels, buffers_);
  }
}

void Frame::set_tile(std::size_t first, std::size_t count) {
  set_kernel_args(camera_rays_, scene_, camera_args_, cl_uint(spp_), seed_, cl_uint(first), cl_uint(count),
                  buffers_.camera_hits, buffers_.traversal_totals, buffers_.gbuffer, gbuffer_planes_);
  if (wavefront_ || !ao_kernel_()) return;  // the wavefront sets its own kernels' tile
  set_kernel_args(ao_kernel_, scene_, ao_args_, cl_uint(first), cl_uint(count), buffers_.camera_hits, buffers_.ao,
                  buffers_.ao_second_moment, buffers_.ao_variance, buffers_.coverage, buffers_.secondary_rays,
                  buffers_.traversal_totals);
}

void Frame::enqueue_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count) {
  set_tile(first, count);
  launch(queue, camera_rays_, camera_items(count), camera_group_);
  enqueue_ao(queue, first, count);
}

void Frame::enqueue_tile(cl::CommandQueue& queue, std::size_t first, std::size_t count,
                         const std::vector<cl_uint4>& points) {
  if (points.size() != count * spp_)
    throw std::logic_error("Frame: " + std::to_string(points.size()) + " points for " + std::to_string(count) +
                           " pixels of " + std::to_string(spp_) + " samples");
  set_tile(first, count);
  queue.enqueueWriteBuffer(buffers_.camera_hits, CL_TRUE, 0, points.size() * sizeof(cl_uint4), points.data());
  enqueue_ao(queue, first, count);
}

void Frame::enqueue_ao(cl::CommandQueue& queue, std::size_t first, std::size_t count) {
  if (wavefront_)
    wavefront_->enqueue_tile(queue, first, count);
  else if (ao_kernel_())
    launch(queue, ao_kernel_, count, ao_group_);
}

std::size_t Frame::camera_items(std::size_t pixels) const {
  return (pixels * spp_ + camera_rays_per_item_ - 1) / camera_rays_per_item_;
}

void Frame::enqueue_empty_tiles(cl::CommandQueue& queue) {
  set_tile(0, 0);
  launch_empty(queue, camera_rays_, camera_items(tile_pixels_), camera_group_);
  if (wavefront_)
    wavefront_->enqueue_empty_tiles(queue, tile_pixels_);
  else if (ao_kernel_())
    launch_empty(queue, ao_kernel_, tile_pixels_, ao_group_);
}

void Frame::enqueue_read_back(cl::CommandQueue& queue, RenderResult& result, cl_uint* secondary_rays) {
  const auto read_floats = [&](const cl::Buffer& buffer, std::vector<float>& into) {
    if (into.size() != pixels_) throw std::logic_error("Frame: read-back into an image of another size");
    read_buffer(queue, buffer, false, 0, pixels_ * sizeof(cl_float), into.data());
  };
  read_floats(buffers_.ao, result.ao);
  if (!result.ao_second_moment.empty()) read_floats(buffers_.ao_second_moment, result.ao_second_moment);
  if (!result.variance.empty()) read_floats(buffers_.ao_variance, result.variance);
  read_buffer(queue, buffers_.coverage, false, 0, pixels_ * sizeof(cl_uchar), result.coverage.data());
  if (buffers_.secondary_rays())
    read_buffer(queue, buffers_.secondary_rays, false, 0, pixels_ * sizeof(cl_uint), secondary_rays);
}

TraversalTotals Frame::traversal_totals(cl::CommandQueue& queue) const {
  cl_ulong totals[4];
  read_buffer(queue, buffers_.traversal_totals, true, 0, sizeof totals, totals);
  return {totals[0], totals[1], totals[2], totals[3]};
}

std::string Frame::launch_signature() const {
  const cl::Program program = camera_rays_.getInfo<CL_KERNEL_PROGRAM>();
  const std::string ao = wavefront_ ? wavefront_->launch_signature()
                         : ao_kernel_()
                             ? ao_kernel_.getInfo<CL_KERNEL_FUNCTION_NAME>() + " " + std::to_string(ao_group_)
                             : "no AO";
  return std::to_string(reinterpret_cast<std::uintptr_t>(program())) + " " + std::to_string(camera_group_) + " " + ao +
         " tile " + std::to_string(tile_pixels_);
}

}  // namespace mbao
