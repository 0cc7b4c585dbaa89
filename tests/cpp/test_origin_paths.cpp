// Rays that leave one point and walk its path down the kd-tree (OriginPath in
// kernels/kd_traversal.h) find what rays walking from the root find, bit for
// bit and node for node, with every traversal, wherever the point lies: in the
// scene, on a split plane, on the scene's box or outside it. Renders with paths
// are the images of renders without.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "opencl/compute_context.h"
#include "opencl/devices.h"
#include "opencl/kernel_sources.h"
#include "render/device_scene.h"
#include "render/render_plan.h"
#include "render/renderer.h"
#include "scene/cornell_box.h"
#include "scene/gltf_loader.h"

namespace mbao {
namespace {

// Appended to trace.cl's program: each work item locates one point and traces
// its rays from there twice, along the path and from the root.
constexpr const char* kRaysFromOnePoint = R"CL(
__kernel void rays_from_one_point(MBAO_SCENE_PARAMS, __global const float4* points,
                                  __global const float4* directions, uint rays_per_point,
                                  uint point_count, __global uint4* along_path,
                                  __global uint4* from_root, __global uint4* along_path_counts,
                                  __global uint4* from_root_counts, __global uint* path_lengths) {
  const uint i = get_global_id(0);
  if (i >= point_count) return;
  const SceneView scene = MBAO_SCENE_VIEW();
  RayOrigin origin;
  locate_ray_origin(&scene, points[i].xyz, &origin);
  path_lengths[i] = origin.path.length;
  for (uint j = 0; j < rays_per_point; ++j) {
    const uint ray = i * rays_per_point + j;
    const float4 d = directions[ray];
    const int any_hit = j & 1;
    Hit a, b;
    TraversalCounts ca = no_traversal_counts(), cb = no_traversal_counts();
    trace_ray_from(&scene, &origin, d.xyz, d.w, any_hit, &a, &ca);
    trace_ray(&scene, origin.point, d.xyz, d.w, any_hit, &b, &cb);
    along_path[ray] = (uint4)(as_uint(a.t), a.triangle, as_uint(a.b1), as_uint(a.b2));
    from_root[ray] = (uint4)(as_uint(b.t), b.triangle, as_uint(b.b1), as_uint(b.b2));
    along_path_counts[ray] = (uint4)(ca.nodes, ca.leaves, ca.triangles, ca.restarts);
    from_root_counts[ray] = (uint4)(cb.nodes, cb.leaves, cb.triangles, cb.restarts);
  }
}
)CL";

constexpr std::uint32_t kRaysPerPoint = 8;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Small triangles spread through the unit cube, with a few large ones: a tree
// deep enough for long paths.
std::shared_ptr<const Scene> triangle_soup(std::size_t n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  TriangleMesh mesh;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 center(unit(rng), unit(rng), unit(rng));
    const float size = 0.2f * std::pow(unit(rng), 3.0f);
    for (int k = 0; k < 3; ++k)
      mesh.positions.push_back(center + size * glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f));
    const auto base = std::uint32_t(3 * i);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return std::make_shared<Scene>(std::move(mesh), "soup");
}

struct Cell {
  KdNode node;
  Bounds3 bounds;
};

// Every interior node of the tree with its cell.
void interior_cells(const KdTree& tree, std::uint32_t index, const Bounds3& bounds, std::vector<Cell>& cells) {
  const KdNode node = tree.nodes[index];
  if (kd_is_leaf(node)) return;
  cells.push_back({node, bounds});
  Bounds3 below = bounds, above = bounds;
  below.hi[kd_axis(node)] = above.lo[kd_axis(node)] = kd_split(node);
  interior_cells(tree, index + 1, below, cells);
  interior_cells(tree, kd_above_child(node), above, cells);
}

struct Points {
  std::vector<cl_float4> points;
  std::size_t on_planes_begin = 0;  // from here on, triples: on a split plane, a float step above it and below it
  std::size_t on_planes = 0;
};

// Points in and around the scene's box (a tenth of its size beyond it), on its
// faces, and on split planes within their nodes' cells, each with its
// neighbours a float step off the plane on either side.
Points points_for(const KdTree& tree, std::mt19937& rng) {
  const glm::vec3 lo = tree.bounds.lo, hi = tree.bounds.hi;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto in = [&](const glm::vec3& from, const glm::vec3& to) {
    return from + (to - from) * glm::vec3(unit(rng), unit(rng), unit(rng));
  };
  Points p;
  auto add = [&](const glm::vec3& v) { p.points.push_back({{v.x, v.y, v.z, 0.0f}}); };
  for (int i = 0; i < 400; ++i) add(in(lo - 0.1f * (hi - lo), hi + 0.1f * (hi - lo)));
  for (int i = 0; i < 60; ++i) {  // on the box's faces
    glm::vec3 v = in(lo, hi);
    v[i % 3] = i % 2 ? hi[i % 3] : lo[i % 3];
    add(v);
  }
  std::vector<Cell> cells;
  interior_cells(tree, 0, tree.bounds, cells);
  std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
  p.on_planes_begin = p.points.size();
  for (; p.on_planes < 300; ++p.on_planes) {
    const Cell& cell = cells[pick(rng)];
    const int axis = int(kd_axis(cell.node));
    glm::vec3 v = in(cell.bounds.lo, cell.bounds.hi);
    v[axis] = kd_split(cell.node);
    glm::vec3 up = v, down = v;
    up[axis] = std::nextafter(v[axis], kInfinity);
    down[axis] = std::nextafter(v[axis], -kInfinity);
    for (const glm::vec3& point : {v, up, down}) add(point);
  }
  return p;
}

// Random unit directions, a third of them along an axis (components exactly
// zero: the descent's division by zero), every fifth ending at a finite t_max.
std::vector<cl_float4> directions_for(std::size_t n, std::mt19937& rng) {
  std::normal_distribution<float> normal;
  std::uniform_int_distribution<int> axis(0, 5);
  std::vector<cl_float4> d(n);
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 v(normal(rng), normal(rng), normal(rng));
    if (i % 3 == 0) {
      const int a = axis(rng);
      v = glm::vec3(0.0f);
      v[a % 3] = a < 3 ? 1.0f : -1.0f;
    }
    v = glm::normalize(v);
    d[i] = {{v.x, v.y, v.z, i % 5 == 0 ? 0.3f : kInfinity}};
  }
  return d;
}

template <typename T>
cl::Buffer buffer_of(ComputeContext& compute, std::vector<T>& data) {
  return cl::Buffer(compute.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(T), data.data());
}

template <typename T>
std::vector<T> read(ComputeContext& compute, const cl::Buffer& buffer, std::size_t n) {
  std::vector<T> data(n);
  compute.queue().enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(T), data.data());
  return data;
}

bool same_bits(const cl_uint4& a, const cl_uint4& b) { return std::memcmp(&a, &b, sizeof(cl_uint4)) == 0; }

TEST(OriginPaths, RaysAlongAPathFindWhatRaysFromTheRootFind) {
  ComputeContext compute(default_device());
  const std::shared_ptr<const Scene> scene = triangle_soup(6000);
  const KdTree& tree = *scene->kd_tree();
  ASSERT_EQ(scene->render_origin(), glm::vec3(0.0f));  // the points below are in the device's frame
  ASSERT_GE(tree.stats.max_depth, 16);
  const bool indexed = plans_indexed_triangles(compute.device(), scene->mesh().triangles.size());
  const DeviceScene device_scene(compute.context(), compute.queue(), *scene, scene->kd_tree(), false,
                                 device_profile(compute.device()).shares_host_memory, indexed);
  std::mt19937 rng(3);
  Points p = points_for(tree, rng);
  std::vector<cl_float4> directions = directions_for(p.points.size() * kRaysPerPoint, rng);
  const std::size_t rays = directions.size();
  const cl::Program::Sources source{kernel_program_source("trace.cl") + kRaysFromOnePoint};

  for (const Traversal traversal : {Traversal::Restart, Traversal::PushDown, Traversal::ShortStack, Traversal::Stack})
    for (const int load_both_children : {0, 1}) {
      if (load_both_children && traversal != Traversal::Stack) continue;
      SCOPED_TRACE(to_string(traversal) + (load_both_children ? ", both children loaded" : ""));
      cl::Program program(compute.context(), source);
      const std::string options = "-DMBAO_TRAVERSAL=" + std::to_string(int(traversal)) +
                                  " -DMBAO_COUNT_TRAVERSAL=1 -DMBAO_ORIGIN_PATHS=1 -DMBAO_LOAD_BOTH_CHILDREN=" +
                                  std::to_string(load_both_children) +
                                  " -DMBAO_INDEXED_TRIANGLES=" + std::to_string(int(indexed));
      program.build(options.c_str());
      cl::Kernel kernel(program, "rays_from_one_point");
      cl::Buffer points = buffer_of(compute, p.points), dirs = buffer_of(compute, directions);
      const cl::Buffer along(compute.context(), CL_MEM_WRITE_ONLY, rays * sizeof(cl_uint4));
      const cl::Buffer root(compute.context(), CL_MEM_WRITE_ONLY, rays * sizeof(cl_uint4));
      const cl::Buffer along_counts(compute.context(), CL_MEM_WRITE_ONLY, rays * sizeof(cl_uint4));
      const cl::Buffer root_counts(compute.context(), CL_MEM_WRITE_ONLY, rays * sizeof(cl_uint4));
      const cl::Buffer lengths(compute.context(), CL_MEM_WRITE_ONLY, p.points.size() * sizeof(cl_uint));
      set_kernel_args(kernel, device_scene, points, dirs, kRaysPerPoint, cl_uint(p.points.size()), along, root,
                      along_counts, root_counts, lengths);
      compute.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(p.points.size()));

      const auto hits_along = read<cl_uint4>(compute, along, rays), hits_root = read<cl_uint4>(compute, root, rays);
      const auto counts_along = read<cl_uint4>(compute, along_counts, rays);
      const auto counts_root = read<cl_uint4>(compute, root_counts, rays);
      std::size_t differing_hits = 0, differing_counts = 0, hits = 0;
      for (std::size_t r = 0; r < rays; ++r) {
        differing_hits += !same_bits(hits_along[r], hits_root[r]);
        differing_counts += !same_bits(counts_along[r], counts_root[r]);
        hits += hits_root[r].s[1] != ~0u;
      }
      EXPECT_EQ(differing_hits, 0u);
      EXPECT_EQ(differing_counts, 0u);
      EXPECT_GT(hits, rays / 4);  // not an agreement on misses alone

      // The paths are long, and a point on a plane stops its path there, where
      // the points a float step off it on either side go on into the children.
      const auto length = read<cl_uint>(compute, lengths, p.points.size());
      double total = 0.0;
      for (std::size_t i = 0; i < p.on_planes_begin; ++i) total += length[i];
      EXPECT_GT(total / double(p.on_planes_begin), 10.0);
      std::size_t stopped = 0;
      for (std::size_t i = 0; i < p.on_planes; ++i) {
        const std::size_t on = p.on_planes_begin + 3 * i;
        stopped += length[on] < std::min(length[on + 1], length[on + 2]);
      }
      EXPECT_EQ(stopped, p.on_planes);
    }
}

RenderSettings small(std::int64_t bounces, bool origin_paths) {
  RenderSettings s;
  s.width = s.height = 48;
  s.bounces = bounces;
  s.traversal_stats = true;
  s.origin_paths = origin_paths;
  return s;
}

void expect_same_render(const std::shared_ptr<const Scene>& scene, const Camera& camera, RenderSettings settings) {
  Renderer& renderer = Renderer::for_device(default_device());
  settings.origin_paths = false;
  const RenderResult from_root = renderer.render(scene, camera, settings);
  settings.origin_paths = true;
  const RenderResult along = renderer.render(scene, camera, settings);
  EXPECT_NE(along.stats.kernel_options.find("-DMBAO_ORIGIN_PATHS=1"), std::string::npos);
  EXPECT_NE(from_root.stats.kernel_options.find("-DMBAO_ORIGIN_PATHS=0"), std::string::npos);
  ASSERT_EQ(along.ao.size(), from_root.ao.size());
  EXPECT_EQ(std::memcmp(along.ao.data(), from_root.ao.data(), along.ao.size() * sizeof(float)), 0);
  EXPECT_EQ(along.stats.rays_secondary, from_root.stats.rays_secondary);
  EXPECT_GT(along.stats.rays_secondary, 0u);
  ASSERT_TRUE(along.stats.traversal && from_root.stats.traversal);
  EXPECT_EQ(along.stats.traversal->nodes, from_root.stats.traversal->nodes);
  EXPECT_EQ(along.stats.traversal->leaves, from_root.stats.traversal->leaves);
  EXPECT_EQ(along.stats.traversal->triangles, from_root.stats.traversal->triangles);
}

// Both estimators and organisations, several bounces, a distance limit and jittered camera samples.
TEST(OriginPaths, RendersWithPathsAreTheImagesOfRendersWithout) {
  const auto cornell = cornell_box();
  for (const Estimator estimator : {Estimator::Branching, Estimator::Path})
    for (std::int64_t b : {1, 3}) {
      SCOPED_TRACE(to_string(estimator) + ", b=" + std::to_string(b));
      RenderSettings s = small(b, true);
      s.estimator = estimator;
      expect_same_render(cornell, *cornell->camera(), s);
    }
  RenderSettings s = small(2, true);
  s.organisation = KernelOrganisation::Wavefront;
  s.max_distance = 300.0f;
  s.spp = 2;
  s.rho = 0.6f;
  expect_same_render(cornell, *cornell->camera(), s);
}

// Sponza: a deep tree, alpha masks, shading normals and the camera's distance limit.
TEST(OriginPaths, SponzaWithPathsIsTheImageWithout) {
  const char* dir = std::getenv("MBAO_SHARED_SCENES");
  const std::filesystem::path folder =
      (dir ? std::filesystem::path(dir) : std::filesystem::path(MBAO_SOURCE_DIR).parent_path() / "shared" / "scenes") /
      "sponza";
  if (!std::filesystem::exists(folder / "scene.glb")) GTEST_SKIP() << "no shared scene at " << folder;
  const auto sponza = load_gltf((folder / "scene.glb").string());
  const Camera camera = Camera::load((folder / "camera.json").string());
  RenderSettings s = small(2, true);
  s.max_distance = *camera.max_distance;
  expect_same_render(sponza, camera, s);
}

}  // namespace
}  // namespace mbao
