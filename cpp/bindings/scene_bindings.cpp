#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>
#include <filesystem>

#include "bindings/bindings.h"
#include "bindings/pickle.h"
#include "scene/cornell_box.h"
#include "scene/assimp_loader.h"
#include "scene/gltf_loader.h"

namespace py = pybind11;

namespace mbao::bindings {
namespace {

// width / height of a render, refused unless both are at least 1.
float aspect_of(std::int64_t width, std::int64_t height) {
  if (width < 1 || height < 1)
    throw std::invalid_argument("width and height must be >= 1, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  return float(width) / float(height);
}

using Vec3 = std::array<float, 3>;

py::tuple to_tuple(const glm::vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

py::dict base_color_dict(const BaseColor& c) {
  py::dict d;
  d["factor"] = py::make_tuple(c.factor[0], c.factor[1], c.factor[2], c.factor[3]);
  d["image"] = c.image.empty() ? py::object(py::none())
                               : py::bytes(reinterpret_cast<const char*>(c.image.data()), c.image.size());
  d["texcoord"] = c.texcoord;
  d["wrap"] = py::make_tuple(to_string(c.wrap_s), to_string(c.wrap_t));
  return d;
}
glm::vec3 to_vec3(const Vec3& a) { return {a[0], a[1], a[2]}; }

// A read-only (rows, 3) view of vec3 data owned by `owner`.
template <typename T, typename V>
py::array rows_of_three(const std::vector<V>& data, py::handle owner) {
  static_assert(sizeof(V) == 3 * sizeof(T), "tightly packed vectors");
  py::array_t<T> array({py::ssize_t(data.size()), py::ssize_t(3)}, reinterpret_cast<const T*>(data.data()), owner);
  array.attr("setflags")(py::arg("write") = false);
  return std::move(array);
}

}  // namespace

py::dict tree_stats_dict(const KdTreeStats& s) {
  py::dict d;
  d["nodes"] = s.nodes;
  d["leaves"] = s.leaves;
  d["empty_leaves"] = s.empty_leaves;
  d["max_depth"] = s.max_depth;
  d["mean_triangles_per_leaf"] = s.mean_triangles_per_leaf;
  d["leaf_references"] = s.leaf_references;
  d["degenerate_triangles"] = s.degenerate_triangles;
  d["sah_cost"] = s.sah_cost;
  d["build_ms"] = s.build_ms;
  d["memory_bytes"] = s.memory_bytes;
  return d;
}

namespace {

TriangleMesh mesh_from_arrays(const py::array_t<float, py::array::c_style>& vertices,
                              const py::array_t<std::uint32_t, py::array::c_style>& indices,
                              const std::optional<py::array_t<float, py::array::c_style>>& normals) {
  TriangleMesh mesh;
  const std::size_t n = std::size_t(vertices.shape(0)), m = std::size_t(indices.shape(0));
  mesh.positions.resize(n);
  mesh.triangles.resize(m);
  std::memcpy(mesh.positions.data(), vertices.data(), n * sizeof(glm::vec3));
  std::memcpy(mesh.triangles.data(), indices.data(), m * sizeof(glm::uvec3));
  if (normals) {
    mesh.normals.resize(std::size_t(normals->shape(0)));
    std::memcpy(mesh.normals.data(), normals->data(), mesh.normals.size() * sizeof(glm::vec3));
  }
  return mesh;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Camera>(m, "Camera", R"doc(
A pinhole camera (SPEC 3.1): right-handed, Y up as in glTF.

Camera(eye, target, up=(0, 1, 0), vfov_deg=60.0, max_distance=None)

``vfov_deg`` is the full vertical field of view, in degrees. ``max_distance``
is the AO radius the camera suggests (camera.json's, a glTF camera's extras),
in world units, or None: a render or bake given no ``max_distance`` of its own
takes it (SPEC 1), and says so in ``stats["max_distance_source"]``.)doc")
      .def(py::init([](const Vec3& eye, const Vec3& target, const Vec3& up, float vfov_deg,
                       std::optional<float> max_distance) {
             Camera camera;
             camera.eye = to_vec3(eye);
             camera.target = to_vec3(target);
             camera.up = to_vec3(up);
             camera.vfov_deg = vfov_deg;
             camera.max_distance = max_distance;
             camera.validate();
             return camera;
           }),
           py::arg("eye"), py::arg("target"), py::arg("up") = Vec3{0.0f, 1.0f, 0.0f}, py::arg("vfov_deg") = 60.0f,
           py::arg("max_distance") = py::none())
      .def_static(
          "load", [](const std::filesystem::path& path) { return Camera::load(path.string()); }, py::arg("path"),
          "Reads a camera.json file (SPEC 3.1.1).")
      .def_property_readonly("eye", [](const Camera& c) { return to_tuple(c.eye); })
      .def_property_readonly("target", [](const Camera& c) { return to_tuple(c.target); })
      .def_property_readonly("up", [](const Camera& c) { return to_tuple(c.up); })
      .def_property_readonly("vfov_deg", [](const Camera& c) { return c.vfov_deg; })
      .def_property_readonly("max_distance", [](const Camera& c) { return c.max_distance; })
      .def(py::pickle(&camera_state, &camera_from_state))
      .def("__repr__", [](const Camera& c) {
        auto v = [](const glm::vec3& p) {
          return "(" + py::repr(py::float_(p.x)).cast<std::string>() + ", " +
                 py::repr(py::float_(p.y)).cast<std::string>() + ", " + py::repr(py::float_(p.z)).cast<std::string>() +
                 ")";
        };
        const std::string radius =
            c.max_distance ? ", max_distance=" + py::repr(py::float_(*c.max_distance)).cast<std::string>() : "";
        return "Camera(eye=" + v(c.eye) + ", target=" + v(c.target) + ", up=" + v(c.up) +
               ", vfov_deg=" + py::repr(py::float_(c.vfov_deg)).cast<std::string>() + radius + ")";
      });

  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", R"doc(
Triangles in world space, ready to render: from ``mbao.load``, ``mbao.cornell_box``
or, as ``mbao.Mesh``, from arrays. The kd-tree is built on first use and kept,
so later renders of the same scene do not rebuild it.)doc")
      .def(py::init([]() -> std::shared_ptr<Scene> {
        throw py::type_error(
            "mbao.Scene() makes nothing: a scene comes from mbao.load(path), mbao.cornell_box() or "
            "mbao.Mesh(vertices, indices)");
      }))
      .def_property_readonly(
          "vertices",
          [](py::object self) { return rows_of_three<float>(self.cast<const Scene&>().mesh().positions, self); },
          "(N, 3) float32 vertex positions in world space (read-only).")
      .def_property_readonly(
          "indices",
          [](py::object self) {
            return rows_of_three<std::uint32_t>(self.cast<const Scene&>().mesh().triangles, self);
          },
          "(M, 3) uint32 vertex indices of the triangles (read-only).")
      .def_property_readonly(
          "normals",
          [](py::object self) -> py::object {
            const TriangleMesh& mesh = self.cast<const Scene&>().mesh();
            if (!mesh.has_normals()) return py::none();
            return rows_of_three<float>(mesh.normals, self);
          },
          "(N, 3) float32 vertex normals, zero where a vertex has none; None without normals.")
      .def_property_readonly(
          "bounds", [](const Scene& s) { return py::make_tuple(to_tuple(s.bounds().lo), to_tuple(s.bounds().hi)); },
          "(lo, hi) corners of the box around the triangles.")
      .def_property_readonly(
          "camera", [](const Scene& s) { return s.camera(); },
          "The scene's own camera (the Cornell box's, a glTF file's first perspective camera) or None.")
      .def(
          "default_camera",
          [](const Scene& s, std::int64_t width, std::int64_t height) {
            return s.default_camera(aspect_of(width, height));
          },
          py::arg("width"), py::arg("height"),
          "The camera a render of this size uses when given none: the scene's own, else one framing it.")
      .def(
          "framing_camera",
          [](const Scene& s, std::int64_t width, std::int64_t height) {
            return Camera::framing(s.bounds(), aspect_of(width, height));
          },
          py::arg("width"), py::arg("height"),
          "The camera that frames the whole scene in a render of this size (SPEC 3.1), whatever camera the "
          "scene has: what camera=\"frame\" renders from.")
      .def_property_readonly("name", &Scene::name)
      .def_property_readonly("warnings", &Scene::warnings, "What loading skipped, one sentence each.")
      .def_property_readonly("triangle_count", [](const Scene& s) { return s.mesh().triangles.size(); })
      .def_property_readonly(
          "alpha_masks",
          [](const Scene& s) -> py::object {
            const AlphaMasks& masks = s.masks();
            if (masks.empty()) return py::none();
            py::dict d;
            d["textures"] = masks.textures.size();
            d["masked_triangles"] = masks.triangles.size();
            d["texels"] = masks.texels.size();
            d["bytes"] = masks.bytes();
            return std::move(d);
          },
          "None without MASK materials; else counts of alpha textures, masked triangles, texels and bytes.")
      .def(
          "build",
          [](const Scene& s) {
            KdTreeStats stats;
            {
              py::gil_scoped_release release;
              stats = s.kd_tree()->stats;
            }
            return tree_stats_dict(stats);
          },
          "Builds the kd-tree now (if not yet built) and returns its statistics: nodes, leaves, "
          "empty_leaves, max_depth, mean_triangles_per_leaf, leaf_references, sah_cost, build_ms, memory_bytes.")
      .def(
          "kd_tree",
          [](const Scene& s) {
            const std::shared_ptr<const KdTree> tree = s.kd_tree();
            py::dict d;
            static_assert(sizeof(KdNode) == 2 * sizeof(std::uint32_t), "KdNode is two words");
            py::array_t<std::uint32_t> nodes({py::ssize_t(tree->nodes.size()), py::ssize_t(2)});
            std::memcpy(nodes.mutable_data(), tree->nodes.data(), tree->nodes.size() * sizeof(KdNode));
            d["nodes"] = nodes;
            const std::vector<std::uint32_t> node_rows = kd_node_rows(*tree);
            d["node_rows"] = py::array_t<std::uint32_t>(py::ssize_t(node_rows.size()), node_rows.data());
            d["bounds"] = py::make_tuple(to_tuple(tree->bounds.lo), to_tuple(tree->bounds.hi));
            d["origin"] = to_tuple(s.render_origin());
            d["stats"] = tree_stats_dict(tree->stats);
            return d;
          },
          R"doc(The kd-tree as the kernels read it (kernels/mbao/kd_node.h), for inspection:
"nodes" (K, 2) uint32 words (header, payload): the nodes depth first, each leaf's entries
(triangle ids, the top bit set where the triangle has an alpha mask) in the words after it,
where its payload counts them from the start; "node_rows", the rows of "nodes" that are
the tree's nodes, depth first; "bounds", "stats", and
"origin": the tree (its bounds and split planes) is in coordinates relative to this point,
a corner of the scene where it lies far from the world origin (Scene::render_origin), so that
rounding scales with the scene's size wherever it lies.)doc")
      .def_property_readonly(
          "uv_sets",
          [](const Scene& s) -> py::object {
            const UvSets& uv = s.uv_sets();
            if (!uv.loaded) return py::none();
            py::list sets;
            for (const std::vector<glm::vec2>& set : uv.sets) {
              py::array_t<float> array({py::ssize_t(set.size()), py::ssize_t(2)});
              std::memcpy(array.mutable_data(), set.data(), set.size() * sizeof(glm::vec2));
              sets.append(array);
            }
            py::list materials;
            for (const MaterialUvs& m : uv.materials) {
              py::dict d;
              d["name"] = m.name;
              d["occlusion_texcoord"] =
                  m.occlusion_texcoord < 0 ? py::object(py::none()) : py::int_(m.occlusion_texcoord);
              d["wrap"] = py::make_tuple(to_string(m.wrap_s), to_string(m.wrap_t));
              d["base_color"] = m.base_color ? base_color_dict(*m.base_color) : py::object(py::none());
              materials.append(d);
            }
            py::dict d;
            d["sets"] = sets;
            d["triangle_materials"] =
                py::array_t<std::int32_t>(py::ssize_t(uv.triangle_materials.size()), uv.triangle_materials.data());
            d["materials"] = materials;
            py::list primitives;
            for (const LoadedPrimitive& p : uv.primitives) {
              py::dict entry;
              entry["node"] = p.node;
              entry["mesh"] = p.mesh;
              entry["primitive"] = p.primitive;
              entry["vertices"] = py::make_tuple(p.first_vertex, p.first_vertex + p.vertex_count);
              entry["triangles"] = py::make_tuple(p.first_triangle, p.first_triangle + p.triangle_count);
              primitives.append(entry);
            }
            d["primitives"] = primitives;
            return std::move(d);
          },
          "None unless loaded with texcoords=True; else \"sets\": per TEXCOORD_n an (N, 2) array (NaN for "
          "vertices whose primitive lacks it), \"triangle_materials\" (-1: none) and \"materials\": per "
          "material its name, occlusion_texcoord (None without an occlusion texture), wrap (s, t) and base_color "
          "(None unless read for bake_file: factor, image (PNG or JPEG bytes, or None), texcoord and wrap); "
          "\"primitives\": "
          "per primitive that brought triangles, its node, mesh, primitive and [first, end) of its vertices and "
          "triangles in the scene.")
      .def(py::pickle(&scene_state, &scene_from_state))
      .def("__repr__", [](const Scene& s) {
        return "<mbao.Scene '" + s.name() + "': " + std::to_string(s.mesh().triangles.size()) + " triangles>";
      });

  py::class_<Mesh, Scene, std::shared_ptr<Mesh>>(m, "_Mesh")
      .def(py::init([](const py::array_t<float, py::array::c_style>& vertices,
                       const py::array_t<std::uint32_t, py::array::c_style>& indices,
                       const std::optional<py::array_t<float, py::array::c_style>>& normals) {
             return std::make_shared<Mesh>(mesh_from_arrays(vertices, indices, normals));
           }),
           py::arg("vertices"), py::arg("indices"), py::arg("normals") = py::none())
      .def(py::pickle([](const Mesh& m) { return scene_state(m); }, &mesh_from_state));

  m.def(
      "load",
      [](const std::filesystem::path& path, bool normals, bool texcoords, bool base_colors) -> std::shared_ptr<Scene> {
        LoadOptions options;
        options.normals = normals;
        options.texcoords = texcoords;
        options.base_colors = base_colors;
        return load_scene(path.string(), options);
      },
      py::arg("path"), py::arg("normals") = true, py::arg("texcoords") = false, py::arg("base_colors") = false,
      py::call_guard<py::gil_scoped_release>());
  m.def(
      "cornell_box", []() -> std::shared_ptr<Scene> { return cornell_box(); },
      "The measured Cornell box (SPEC 3.4), in millimetres, with its own camera.");
}

}  // namespace mbao::bindings
