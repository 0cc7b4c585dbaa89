// Scenes and cameras as pickle states: what a scene holds (its mesh, alpha
// masks, UV sets, camera, name and warnings), never what it builds from them
// (the kd-tree, the device buffers), which an unpickled scene builds again.
#include <pybind11/stl.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "bindings/pickle.h"

namespace py = pybind11;

namespace mbao::bindings {
namespace {

// Bumped whenever a state's layout changes: a pickle from another layout is refused by name.
constexpr int kSceneStateVersion = 2;

template <typename T>
py::bytes as_bytes(const std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>, "stored as its bytes");
  return py::bytes(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <typename T>
std::vector<T> from_bytes(const py::handle& bytes, const char* what) {
  const std::string raw = bytes.cast<std::string>();
  if (raw.size() % sizeof(T) != 0)
    throw std::invalid_argument(std::string("unpickling a scene: ") + what + " holds " + std::to_string(raw.size()) +
                                " bytes, not a whole number of its " + std::to_string(sizeof(T)) + "-byte items");
  std::vector<T> v(raw.size() / sizeof(T));
  if (!raw.empty()) std::memcpy(v.data(), raw.data(), raw.size());
  return v;
}

py::tuple mask_state(const AlphaMasks& m) {
  return py::make_tuple(as_bytes(m.textures), as_bytes(m.texels), as_bytes(m.triangles), as_bytes(m.triangle_mask));
}

AlphaMasks masks_from_state(const py::tuple& t) {
  return {from_bytes<MaskTexture>(t[0], "the mask textures"), from_bytes<std::uint8_t>(t[1], "the mask texels"),
          from_bytes<MaskedTriangle>(t[2], "the masked triangles"),
          from_bytes<std::uint32_t>(t[3], "the triangles' masks")};
}

py::object base_color_state(const BaseColor& c) {
  return py::make_tuple(py::make_tuple(c.factor[0], c.factor[1], c.factor[2], c.factor[3]), as_bytes(c.image),
                        c.texcoord, std::uint32_t(c.wrap_s), std::uint32_t(c.wrap_t));
}

BaseColor base_color_from_state(const py::handle& state) {
  const auto [factor, image, texcoord, s, t] =
      state.cast<std::tuple<std::array<float, 4>, py::object, int, std::uint32_t, std::uint32_t>>();
  return {factor, from_bytes<unsigned char>(image, "a base colour image"), texcoord, WrapMode(s), WrapMode(t)};
}

py::tuple uv_state(const UvSets& uv) {
  py::list sets, materials, primitives;
  for (const auto& set : uv.sets) sets.append(as_bytes(set));
  for (const MaterialUvs& m : uv.materials)
    materials.append(py::make_tuple(m.name, m.occlusion_texcoord, std::uint32_t(m.wrap_s), std::uint32_t(m.wrap_t),
                                    m.base_color ? base_color_state(*m.base_color) : py::object(py::none())));
  for (const LoadedPrimitive& p : uv.primitives)
    primitives.append(py::make_tuple(p.node, p.mesh, p.primitive, p.first_vertex, p.vertex_count, p.first_triangle,
                                     p.triangle_count));
  return py::make_tuple(uv.loaded, sets, as_bytes(uv.triangle_materials), materials, primitives);
}

UvSets uvs_from_state(const py::tuple& t) {
  UvSets uv;
  uv.loaded = t[0].cast<bool>();
  for (const py::handle set : t[1].cast<py::list>()) uv.sets.push_back(from_bytes<glm::vec2>(set, "a UV set"));
  uv.triangle_materials = from_bytes<std::int32_t>(t[2], "the triangles' materials");
  for (const py::handle m : t[3].cast<py::list>()) {
    const auto [name, texcoord, s, t_, base_color] =
        m.cast<std::tuple<std::string, int, std::uint32_t, std::uint32_t, py::object>>();
    uv.materials.push_back({name, texcoord, WrapMode(s), WrapMode(t_), std::nullopt});
    if (!base_color.is_none()) uv.materials.back().base_color = base_color_from_state(base_color);
  }
  for (const py::handle p : t[4].cast<py::list>()) {
    const auto v = p.cast<std::tuple<int, int, int, std::size_t, std::size_t, std::size_t, std::size_t>>();
    uv.primitives.push_back({std::get<0>(v), std::get<1>(v), std::get<2>(v), std::get<3>(v), std::get<4>(v),
                             std::get<5>(v), std::get<6>(v)});
  }
  return uv;
}

// The mesh of a scene's state, after checking that this version wrote it.
TriangleMesh mesh_of_state(const py::tuple& t) {
  if (t.size() != 9 || t[0].cast<int>() != kSceneStateVersion)
    throw std::invalid_argument("unpickling a scene: this pickle was made by another version of mbao (scene state " +
                                py::repr(t[0]).cast<std::string>() + ", this one reads " +
                                std::to_string(kSceneStateVersion) + ")");
  return {from_bytes<glm::vec3>(t[2], "the vertices"), from_bytes<glm::uvec3>(t[3], "the triangles"),
          from_bytes<glm::vec3>(t[4], "the normals")};
}

}  // namespace

py::tuple camera_state(const Camera& c) {
  return py::make_tuple(py::make_tuple(c.eye.x, c.eye.y, c.eye.z), py::make_tuple(c.target.x, c.target.y, c.target.z),
                        py::make_tuple(c.up.x, c.up.y, c.up.z), c.vfov_deg, c.max_distance);
}

Camera camera_from_state(const py::tuple& t) {
  const auto vec = [](const py::handle& h) {
    const auto [x, y, z] = h.cast<std::tuple<float, float, float>>();
    return glm::vec3(x, y, z);
  };
  return {vec(t[0]), vec(t[1]), vec(t[2]), t[3].cast<float>(), t[4].cast<std::optional<float>>()};
}

py::tuple scene_state(const Scene& s) {
  const TriangleMesh& mesh = s.mesh();
  const py::object camera = s.camera() ? py::object(camera_state(*s.camera())) : py::object(py::none());
  return py::make_tuple(kSceneStateVersion, s.name(), as_bytes(mesh.positions), as_bytes(mesh.triangles),
                        as_bytes(mesh.normals), camera, s.warnings(), mask_state(s.masks()), uv_state(s.uv_sets()));
}

std::shared_ptr<Scene> scene_from_state(const py::tuple& t) {
  std::optional<Camera> camera;
  if (!t[5].is_none()) camera = camera_from_state(t[5].cast<py::tuple>());
  return std::make_shared<Scene>(mesh_of_state(t), t[1].cast<std::string>(), camera,
                                 t[6].cast<std::vector<std::string>>(), masks_from_state(t[7].cast<py::tuple>()),
                                 uvs_from_state(t[8].cast<py::tuple>()));
}

std::shared_ptr<Mesh> mesh_from_state(const py::tuple& t) { return std::make_shared<Mesh>(mesh_of_state(t)); }

}  // namespace mbao::bindings
