#include "embree_ao.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/timer.h"
#include "mbao/alpha_mask.h"
#include "mbao/philox.h"

namespace bench {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// --- what the kernels compute, in C++ (kernels/sampling.h, surface.h) ---------

Philox4x32 random_block(std::uint32_t pixel, std::uint32_t camera_sample, std::uint32_t bounce, std::uint32_t node,
                        std::uint64_t seed) {
  return philox4x32_10({{pixel, camera_sample, bounce, node}}, std::uint32_t(seed), std::uint32_t(seed >> 32));
}

glm::vec3 cosine_direction(const glm::vec3& n, float u1, float u2) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  const glm::vec3 t(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  const glm::vec3 b(c, sign + n.y * n.y * a, -n.y);
  const float r = std::sqrt(u1), phi = 2.0f * float(M_PI) * u2;
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
}

// SPEC 3.3: a direction below the geometric surface is mirrored in it; false
// for one along the surface, which counts as occluded.
bool mirrored_above(const glm::vec3& geometric_normal, glm::vec3* dir) {
  const float along = glm::dot(*dir, geometric_normal);
  if (along < 0.0f) *dir -= 2.0f * along * geometric_normal;
  return glm::dot(*dir, geometric_normal) > 0.0f;
}

struct Surface {
  glm::vec3 position{0.0f};
  float offset = 0.0f;
  glm::vec3 geometric_normal{0.0f}, shading_normal{0.0f};
};

glm::vec3 leaving_point(const Surface& s) {
  const glm::vec3 offset = s.offset * s.geometric_normal;
  glm::vec3 p = s.position + offset;
  for (int k = 0; k < 3; ++k)
    if (offset[k] != 0.0f) p[k] = std::nextafter(p[k], offset[k] > 0.0f ? kInfinity : -kInfinity);
  return p;
}

struct Ray {
  glm::vec3 origin, dir;
};

// A ray of the AO tree of a camera sample: which sample, bounce and node.
struct TreeRay {
  std::uint32_t slot;  // camera sample within the block
  std::uint32_t bounce, node;
  Ray ray;
};

}  // namespace

struct EmbreeAo::Impl {
  std::shared_ptr<const mbao::Scene> scene;
  unsigned threads = 1;
  RTCDevice device = nullptr;
  RTCScene rtc_scene = nullptr;
  bool shading_normals = false;  // set per render

  static void mask_filter(const RTCFilterFunctionNArguments* args) {
    const auto* self = static_cast<const Impl*>(args->geometryUserPtr);
    const mbao::AlphaMasks& masks = self->scene->masks();
    for (unsigned i = 0; i < args->N; ++i) {
      if (args->valid[i] != -1) continue;
      const std::uint32_t slot = masks.triangle_mask[RTCHitN_primID(args->hit, args->N, i)];
      if (slot == MBAO_NOT_MASKED) continue;
      const MaskedTriangle& t = masks.triangles[slot];
      if (!mask_is_opaque(t, masks.textures[t.texture], masks.texels.data(), RTCHitN_u(args->hit, args->N, i),
                          RTCHitN_v(args->hit, args->N, i)))
        args->valid[i] = 0;
    }
  }

  Surface surface(std::uint32_t triangle, float b1, float b2, const glm::vec3& incoming) const {
    const mbao::TriangleMesh& mesh = scene->mesh();
    const glm::uvec3 v = mesh.triangles[triangle];
    const glm::vec3 p0 = mesh.positions[v.x], p1 = mesh.positions[v.y], p2 = mesh.positions[v.z];
    const float b0 = 1.0f - b1 - b2;
    Surface s;
    s.position = b0 * p0 + b1 * p1 + b2 * p2;
    const glm::vec3 magnitude = glm::max(glm::max(glm::abs(p0), glm::abs(p1)), glm::abs(p2));
    s.offset = 256.0f * std::numeric_limits<float>::epsilon() * std::max({magnitude.x, magnitude.y, magnitude.z});
    glm::vec3 ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    if (glm::dot(ng, incoming) > 0.0f) ng = -ng;
    s.geometric_normal = s.shading_normal = ng;
    if (shading_normals) {
      const glm::vec3 n = b0 * mesh.normals[v.x] + b1 * mesh.normals[v.y] + b2 * mesh.normals[v.z];
      const float length_squared = glm::dot(n, n);
      if (length_squared > 0.0f && std::isfinite(length_squared)) {
        const glm::vec3 ns = n / std::sqrt(length_squared);
        s.shading_normal = glm::dot(ns, ng) < 0.0f ? -ns : ns;
      }
    }
    return s;
  }
};

EmbreeAo::EmbreeAo(std::shared_ptr<const mbao::Scene> scene, unsigned threads, bool robust)
    : impl_(std::make_unique<Impl>()) {
  impl_->scene = std::move(scene);
  impl_->threads = std::max(1u, threads);
  const std::string config = "threads=" + std::to_string(impl_->threads);
  impl_->device = rtcNewDevice(config.c_str());
  if (!impl_->device) throw std::runtime_error("Embree: cannot create a device");
  mbao::Stopwatch clock;
  impl_->rtc_scene = rtcNewScene(impl_->device);
  if (robust) rtcSetSceneFlags(impl_->rtc_scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->rtc_scene, RTC_BUILD_QUALITY_HIGH);  // a static scene: Embree at its best
  const mbao::TriangleMesh& mesh = impl_->scene->mesh();
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.positions.size()));
  std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.triangles.size()));
  std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3));
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  if (!impl_->scene->masks().empty()) {
    rtcSetGeometryUserData(geometry, impl_.get());
    rtcSetGeometryIntersectFilterFunction(geometry, Impl::mask_filter);
    rtcSetGeometryOccludedFilterFunction(geometry, Impl::mask_filter);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->rtc_scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->rtc_scene);
  build_ms_ = clock.elapsed_ms();
}

EmbreeAo::~EmbreeAo() {
  if (impl_->rtc_scene) rtcReleaseScene(impl_->rtc_scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

namespace {

// One frame's settings and the per-sample bookkeeping both tracers share.
struct FrameJob {
  const EmbreeAo& owner;
  mbao::CameraBasis basis;
  glm::vec3 eye;
  const mbao::RenderSettings& s;
  std::size_t pixels, samples_total;

  Ray camera_ray(std::size_t sample_index) const {
    const std::uint32_t pixel = std::uint32_t(sample_index / std::size_t(s.spp));
    const std::uint32_t camera_sample = std::uint32_t(sample_index % std::size_t(s.spp));
    float jx = 0.5f, jy = 0.5f;
    if (s.spp > 1) {
      const Philox4x32 r = random_block(pixel, camera_sample, 0, 0, s.seed);
      jx = philox_unit_float(r.v[0]);
      jy = philox_unit_float(r.v[1]);
    }
    const float px = float(pixel % std::uint32_t(s.width)) + jx, py = float(pixel / std::uint32_t(s.width)) + jy;
    return {eye, basis.direction(px, py, int(s.width), int(s.height))};
  }

  bool bounces_on(std::uint32_t bounce) const { return std::int64_t(bounce) < s.bounces && s.rho > 0.0f; }

  // The AO estimate of a camera sample from its escapes per bounce (as the kernels weigh them).
  float estimate(const std::uint32_t* escapes) const {
    const float inv_samples = 1.0f / float(s.samples);
    float value = 0.0f, weight = inv_samples;
    for (std::int64_t k = 0; k < s.bounces; ++k) {
      value += float(escapes[k]) * weight;
      weight *= s.rho * (s.estimator == mbao::Estimator::Branching ? inv_samples : 1.0f);
    }
    return std::min(value, 1.0f);
  }
};

RTCRayHit single_ray(const Ray& ray, float t_max) {
  RTCRayHit rh{};
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.dir.x;
  rh.ray.dir_y = ray.dir.y;
  rh.ray.dir_z = ray.dir.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = t_max;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

EmbreeFrame EmbreeAo::render(const mbao::Camera& camera, const mbao::RenderSettings& s, Mode mode) const {
  s.validate();
  impl_->shading_normals = s.normals == mbao::NormalMode::Shading && impl_->scene->mesh().has_normals();
  const std::size_t pixels = std::size_t(s.width) * std::size_t(s.height);
  FrameJob job{*this, mbao::CameraBasis(camera), camera.eye, s, pixels, pixels * std::size_t(s.spp)};
  std::vector<float> sample_values(job.samples_total, 1.0f);
  std::vector<std::uint64_t> rays(impl_->threads, 0);
  const std::size_t block = 16;  // camera samples per job: one packet of camera rays
  std::atomic<std::size_t> next_block{0};
  const float t_max = s.radius();
  const Impl& impl = *impl_;

  // A level of a camera sample's AO tree, walked depth first (as the kernel walks it).
  struct Level {
    Surface surface;
    std::uint32_t node, next_child;
  };
  const auto single_rays_worker = [&](unsigned thread) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::vector<std::uint32_t> escapes(std::size_t(s.bounces));
    std::vector<Level> stack;
    for (std::size_t first; (first = next_block.fetch_add(block)) < job.samples_total;) {
      for (std::size_t index = first; index < std::min(first + block, job.samples_total); ++index) {
        const Ray camera_ray = job.camera_ray(index);
        RTCRayHit primary = single_ray(camera_ray, kInfinity);
        rtcIntersect1(impl.rtc_scene, &context, &primary);
        if (primary.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const std::uint32_t pixel = std::uint32_t(index / std::size_t(s.spp));
        const std::uint32_t camera_sample = std::uint32_t(index % std::size_t(s.spp));
        std::fill(escapes.begin(), escapes.end(), 0u);
        stack.clear();
        stack.push_back({impl.surface(primary.hit.primID, primary.hit.u, primary.hit.v, camera_ray.dir), 0, 0});
        while (!stack.empty()) {
          Level& level = stack.back();
          const std::uint32_t children =
              s.estimator == mbao::Estimator::Branching || stack.size() == 1 ? std::uint32_t(s.samples) : 1u;
          if (level.next_child == children) {
            stack.pop_back();
            continue;
          }
          const std::uint32_t c = level.next_child++;
          const std::uint32_t bounce = std::uint32_t(stack.size());
          const std::uint32_t node = s.estimator == mbao::Estimator::Branching
                                         ? level.node * std::uint32_t(s.samples) + c
                                         : (stack.size() == 1 ? c : level.node);
          const Philox4x32 r = random_block(pixel, camera_sample, bounce, node, s.seed);
          glm::vec3 dir =
              cosine_direction(level.surface.shading_normal, philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
          if (!mirrored_above(level.surface.geometric_normal, &dir)) continue;
          ++rays[thread];
          RTCRayHit ray = single_ray({leaving_point(level.surface), dir}, t_max);
          if (!job.bounces_on(bounce)) {
            rtcOccluded1(impl.rtc_scene, &context, &ray.ray);
            if (ray.ray.tfar >= 0.0f) ++escapes[bounce - 1];
            continue;
          }
          rtcIntersect1(impl.rtc_scene, &context, &ray);
          if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            ++escapes[bounce - 1];
            continue;
          }
          const Surface next = impl.surface(ray.hit.primID, ray.hit.u, ray.hit.v, dir);
          stack.push_back({next, node, 0});
        }
        sample_values[index] = job.estimate(escapes.data());
      }
    }
  };

  // Breadth first over a block of 16 camera samples: every bounce's rays go
  // out in packets of 16.
  const auto packet_worker = [&](unsigned thread) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::vector<std::uint32_t> escapes;
    std::vector<TreeRay> queue;
    std::vector<std::pair<TreeRay, Surface>> frontier, next_frontier;
    for (std::size_t first; (first = next_block.fetch_add(block)) < job.samples_total;) {
      const std::size_t count = std::min(block, job.samples_total - first);
      escapes.assign(block * std::size_t(s.bounces), 0u);
      frontier.clear();
      // Camera rays: one packet. Embree wants packets and masks 64-byte aligned.
      alignas(64) RTCRayHit16 packet{};
      alignas(64) int valid[16];
      std::vector<Ray> camera_rays(count);
      for (std::size_t i = 0; i < 16; ++i) {
        valid[i] = i < count ? -1 : 0;
        if (i >= count) continue;
        camera_rays[i] = job.camera_ray(first + i);
        const Ray& ray = camera_rays[i];
        packet.ray.org_x[i] = ray.origin.x, packet.ray.org_y[i] = ray.origin.y, packet.ray.org_z[i] = ray.origin.z;
        packet.ray.dir_x[i] = ray.dir.x, packet.ray.dir_y[i] = ray.dir.y, packet.ray.dir_z[i] = ray.dir.z;
        packet.ray.tnear[i] = 0.0f, packet.ray.tfar[i] = kInfinity, packet.ray.mask[i] = 0xFFFFFFFFu;
        packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, impl.rtc_scene, &context, &packet);
      std::vector<bool> covered(count, false);
      for (std::size_t i = 0; i < count; ++i) {
        if (packet.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
        covered[i] = true;
        frontier.push_back({TreeRay{std::uint32_t(i), 0, 0, camera_rays[i]},
                            impl.surface(packet.hit.primID[i], packet.hit.u[i], packet.hit.v[i], camera_rays[i].dir)});
      }
      for (std::uint32_t bounce = 1; bounce <= std::uint32_t(s.bounces) && !frontier.empty(); ++bounce) {
        queue.clear();
        std::vector<Surface> origins;  // the surface each queued ray leaves
        for (const auto& [parent, surface] : frontier) {
          const std::size_t index = first + parent.slot;
          const std::uint32_t pixel = std::uint32_t(index / std::size_t(s.spp));
          const std::uint32_t camera_sample = std::uint32_t(index % std::size_t(s.spp));
          const bool branching = s.estimator == mbao::Estimator::Branching;
          const std::uint32_t children = branching || bounce == 1 ? std::uint32_t(s.samples) : 1u;
          for (std::uint32_t c = 0; c < children; ++c) {
            const std::uint32_t node =
                branching ? parent.node * std::uint32_t(s.samples) + c : (bounce == 1 ? c : parent.node);
            const Philox4x32 r = random_block(pixel, camera_sample, bounce, node, s.seed);
            glm::vec3 dir =
                cosine_direction(surface.shading_normal, philox_unit_float(r.v[0]), philox_unit_float(r.v[1]));
            if (!mirrored_above(surface.geometric_normal, &dir)) continue;
            queue.push_back({parent.slot, bounce, node, {leaving_point(surface), dir}});
          }
        }
        rays[thread] += queue.size();
        next_frontier.clear();
        const bool need_hits = job.bounces_on(bounce);
        for (std::size_t start = 0; start < queue.size(); start += 16) {
          const std::size_t n = std::min<std::size_t>(16, queue.size() - start);
          alignas(64) RTCRayHit16 rays16{};
          for (std::size_t i = 0; i < 16; ++i) {
            valid[i] = i < n ? -1 : 0;
            if (i >= n) continue;
            const Ray& ray = queue[start + i].ray;
            rays16.ray.org_x[i] = ray.origin.x, rays16.ray.org_y[i] = ray.origin.y, rays16.ray.org_z[i] = ray.origin.z;
            rays16.ray.dir_x[i] = ray.dir.x, rays16.ray.dir_y[i] = ray.dir.y, rays16.ray.dir_z[i] = ray.dir.z;
            rays16.ray.tnear[i] = 0.0f, rays16.ray.tfar[i] = t_max, rays16.ray.mask[i] = 0xFFFFFFFFu;
            rays16.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
          }
          if (need_hits)
            rtcIntersect16(valid, impl.rtc_scene, &context, &rays16);
          else
            rtcOccluded16(valid, impl.rtc_scene, &context, &rays16.ray);
          for (std::size_t i = 0; i < n; ++i) {
            const TreeRay& tree_ray = queue[start + i];
            const bool escaped =
                need_hits ? rays16.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID : rays16.ray.tfar[i] >= 0.0f;
            if (escaped) {
              ++escapes[tree_ray.slot * std::size_t(s.bounces) + bounce - 1];
            } else if (need_hits) {
              next_frontier.push_back(
                  {tree_ray, impl.surface(rays16.hit.primID[i], rays16.hit.u[i], rays16.hit.v[i], tree_ray.ray.dir)});
            }
          }
        }
        std::swap(frontier, next_frontier);
      }
      for (std::size_t i = 0; i < count; ++i)
        if (covered[i]) sample_values[first + i] = job.estimate(&escapes[i * std::size_t(s.bounces)]);
    }
  };

  mbao::Stopwatch clock;
  std::vector<std::thread> workers;
  for (unsigned t = 0; t < impl_->threads; ++t)
    workers.emplace_back(mode == Mode::SingleRays ? std::function<void(unsigned)>(single_rays_worker)
                                                  : std::function<void(unsigned)>(packet_worker),
                         t);
  for (std::thread& w : workers) w.join();
  EmbreeFrame frame;
  frame.ao.resize(pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    float sum = 0.0f;
    for (std::int64_t k = 0; k < s.spp; ++k) sum += sample_values[p * std::size_t(s.spp) + std::size_t(k)];
    frame.ao[p] = sum / float(s.spp);
  }
  frame.frame_ms = clock.elapsed_ms();
  frame.rays_primary = job.samples_total;
  for (std::uint64_t r : rays) frame.rays_secondary += r;
  return frame;
}

}  // namespace bench
