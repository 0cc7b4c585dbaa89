#include "scene/cornell_box.h"

#include <array>

namespace mbao {
namespace {

using Quad = std::array<glm::vec3, 4>;

// Cornell University Program of Computer Graphics, "Cornell Box Data", in
// millimetres. Objects in the order floor, ceiling, light, back wall, right
// wall, left wall, short block (5 quads), tall block (5 quads).
const Quad kQuads[] = {
    {{{552.8f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 559.2f}, {549.6f, 0.0f, 559.2f}}},
    {{{556.0f, 548.8f, 0.0f}, {556.0f, 548.8f, 559.2f}, {0.0f, 548.8f, 559.2f}, {0.0f, 548.8f, 0.0f}}},
    {{{343.0f, 548.8f, 227.0f}, {343.0f, 548.8f, 332.0f}, {213.0f, 548.8f, 332.0f}, {213.0f, 548.8f, 227.0f}}},
    {{{549.6f, 0.0f, 559.2f}, {0.0f, 0.0f, 559.2f}, {0.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 559.2f}}},
    {{{0.0f, 0.0f, 559.2f}, {0.0f, 0.0f, 0.0f}, {0.0f, 548.8f, 0.0f}, {0.0f, 548.8f, 559.2f}}},
    {{{552.8f, 0.0f, 0.0f}, {549.6f, 0.0f, 559.2f}, {556.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 0.0f}}},
    {{{130.0f, 165.0f, 65.0f}, {82.0f, 165.0f, 225.0f}, {240.0f, 165.0f, 272.0f}, {290.0f, 165.0f, 114.0f}}},
    {{{290.0f, 0.0f, 114.0f}, {290.0f, 165.0f, 114.0f}, {240.0f, 165.0f, 272.0f}, {240.0f, 0.0f, 272.0f}}},
    {{{130.0f, 0.0f, 65.0f}, {130.0f, 165.0f, 65.0f}, {290.0f, 165.0f, 114.0f}, {290.0f, 0.0f, 114.0f}}},
    {{{82.0f, 0.0f, 225.0f}, {82.0f, 165.0f, 225.0f}, {130.0f, 165.0f, 65.0f}, {130.0f, 0.0f, 65.0f}}},
    {{{240.0f, 0.0f, 272.0f}, {240.0f, 165.0f, 272.0f}, {82.0f, 165.0f, 225.0f}, {82.0f, 0.0f, 225.0f}}},
    {{{423.0f, 330.0f, 247.0f}, {265.0f, 330.0f, 296.0f}, {314.0f, 330.0f, 456.0f}, {472.0f, 330.0f, 406.0f}}},
    {{{423.0f, 0.0f, 247.0f}, {423.0f, 330.0f, 247.0f}, {472.0f, 330.0f, 406.0f}, {472.0f, 0.0f, 406.0f}}},
    {{{472.0f, 0.0f, 406.0f}, {472.0f, 330.0f, 406.0f}, {314.0f, 330.0f, 456.0f}, {314.0f, 0.0f, 456.0f}}},
    {{{314.0f, 0.0f, 456.0f}, {314.0f, 330.0f, 456.0f}, {265.0f, 330.0f, 296.0f}, {265.0f, 0.0f, 296.0f}}},
    {{{265.0f, 0.0f, 296.0f}, {265.0f, 330.0f, 296.0f}, {423.0f, 330.0f, 247.0f}, {423.0f, 0.0f, 247.0f}}},
};

}  // namespace

std::shared_ptr<Scene> cornell_box() {
  TriangleMesh mesh;
  for (const Quad& quad : kQuads) {
    const auto base = static_cast<unsigned>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), quad.begin(), quad.end());
    // The published quads are split along the v0-v2 diagonal.
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  }
  Camera camera;
  camera.eye = {278.0f, 273.0f, -800.0f};
  camera.target = {278.0f, 273.0f, 0.0f};
  camera.up = {0.0f, 1.0f, 0.0f};
  camera.vfov_deg = 39.3077f;
  return std::make_shared<Scene>(std::move(mesh), "cornell_box", camera);
}

}  // namespace mbao
