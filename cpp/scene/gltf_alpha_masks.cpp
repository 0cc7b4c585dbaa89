#include "scene/gltf_alpha_masks.h"

#include <cctype>
#include <cmath>

#include "core/error.h"
#include "scene/gltf_files.h"
#include "scene/image_alpha.h"
#include "scene/texture_files.h"
#include "scene/wrap_mode.h"

namespace mbao {
namespace {

// A URI's %XX escapes decoded (glTF URIs are percent-encoded).
std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace

bool keep_data_uri_images(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                          const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && image->uri.empty()) image->image.assign(bytes, bytes + size);
  return true;
}

GltfAlphaMasks::GltfAlphaMasks(const tinygltf::Model& model, const AccessorReader& accessors, std::string path,
                               std::filesystem::path base_dir, std::vector<std::string>& warnings)
    : model_(model),
      accessors_(accessors),
      path_(std::move(path)),
      base_dir_(std::move(base_dir)),
      warnings_(warnings),
      builder_(path_) {}

GltfAlphaMasks::Material GltfAlphaMasks::material(int index) {
  const auto found = materials_.find(index);
  if (found != materials_.end()) return found->second;
  return materials_[index] = resolve(index);
}

GltfAlphaMasks::Material GltfAlphaMasks::resolve(int index) {
  if (index < 0) return {};
  if (std::size_t(index) >= model_.materials.size())
    throw LoadError(path_ + ": material " + std::to_string(index) + " does not exist");
  const tinygltf::Material& m = model_.materials[std::size_t(index)];
  if (m.alphaMode != "MASK") return {};
  const std::string what = "material " + std::to_string(index);
  const auto& base = m.pbrMetallicRoughness;
  const float factor = base.baseColorFactor.size() == 4 ? float(base.baseColorFactor[3]) : 1.0f;
  const float cutoff = float(m.alphaCutoff);
  const auto constant = [&](float alpha) {
    Material constant_material;
    constant_material.coverage = alpha < cutoff ? Coverage::Transparent : Coverage::Opaque;
    return constant_material;
  };
  if (base.baseColorTexture.index < 0) return constant(factor);
  const std::optional<std::uint32_t> texture = mask_texture(base.baseColorTexture.index, factor, cutoff, what);
  if (!texture) return {};                                   // an image that cannot be read: opaque, with a warning
  if (*texture == MBAO_NOT_MASKED) return constant(factor);  // an image without alpha
  Material material;
  material.coverage = Coverage::Masked;
  material.texcoord_set = base.baseColorTexture.texCoord;
  material.texture = *texture;
  read_texture_transform(base.baseColorTexture, what + " baseColorTexture", material);
  return material;
}

// KHR_texture_transform on the mask's texture (SPEC 3.2): its matrix
// translation(offset) * rotation(rotation) * scale(scale), with the rotation
// counter-clockwise in UV space as the extension defines it, and its texCoord
// in place of the texture's.
void GltfAlphaMasks::read_texture_transform(const tinygltf::TextureInfo& info, const std::string& what,
                                            Material& material) const {
  const auto found = info.extensions.find("KHR_texture_transform");
  if (found == info.extensions.end()) return;
  const tinygltf::Value& transform = found->second;
  const auto number = [&](const tinygltf::Value& value, const std::string& name) {
    if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
      throw LoadError(path_ + ": " + what + " KHR_texture_transform " + name + " is not a finite number");
    return value.GetNumberAsDouble();
  };
  const auto pair = [&](const char* name, double fallback) {
    if (!transform.Has(name)) return std::array<double, 2>{fallback, fallback};
    const tinygltf::Value& value = transform.Get(name);
    if (!value.IsArray() || value.ArrayLen() != 2)
      throw LoadError(path_ + ": " + what + " KHR_texture_transform " + name + " is not an array of 2 numbers");
    return std::array<double, 2>{number(value.Get(0), name), number(value.Get(1), name)};
  };
  const std::array<double, 2> offset = pair("offset", 0.0), scale = pair("scale", 1.0);
  const double rotation = transform.Has("rotation") ? number(transform.Get("rotation"), "rotation") : 0.0;
  const double c = std::cos(rotation), s = std::sin(rotation);
  material.uv_transform = {float(c * scale[0]),  float(s * scale[1]), float(offset[0]),
                           float(-s * scale[0]), float(c * scale[1]), float(offset[1])};
  if (transform.Has("texCoord")) {
    const tinygltf::Value& set = transform.Get("texCoord");
    if (!set.IsInt() || set.GetNumberAsInt() < 0)
      throw LoadError(path_ + ": " + what + " KHR_texture_transform texCoord is not a set number");
    material.texcoord_set = set.GetNumberAsInt();
  }
}

std::vector<float> GltfAlphaMasks::Material::transformed(std::vector<float> uv) const {
  const std::array<float, 6>& m = uv_transform;
  for (std::size_t i = 0; i + 1 < uv.size(); i += 2) {
    const float u = uv[i], v = uv[i + 1];
    uv[i] = m[0] * u + m[1] * v + m[2];
    uv[i + 1] = m[3] * u + m[4] * v + m[5];
  }
  return uv;
}

std::optional<std::uint32_t> GltfAlphaMasks::mask_texture(int texture_index, float alpha_factor, float cutoff,
                                                          const std::string& what) {
  if (std::size_t(texture_index) >= model_.textures.size())
    throw LoadError(path_ + ": " + what + " uses texture " + std::to_string(texture_index) + ", which does not exist");
  const tinygltf::Texture& texture = model_.textures[std::size_t(texture_index)];
  const std::string texture_name = "texture " + std::to_string(texture_index);
  if (texture.source < 0 || std::size_t(texture.source) >= model_.images.size())
    throw LoadError(path_ + ": " + texture_name + " has no image (source " + std::to_string(texture.source) + ")");
  std::uint32_t wrap = MBAO_WRAP_REPEAT | (MBAO_WRAP_REPEAT << 2);
  if (texture.sampler >= 0) {
    if (std::size_t(texture.sampler) >= model_.samplers.size())
      throw LoadError(path_ + ": " + texture_name + " uses sampler " + std::to_string(texture.sampler) +
                      ", which does not exist");
    const tinygltf::Sampler& sampler = model_.samplers[std::size_t(texture.sampler)];
    wrap = std::uint32_t(wrap_mode_of_gltf(sampler.wrapS)) | (std::uint32_t(wrap_mode_of_gltf(sampler.wrapT)) << 2);
  }
  const auto key = std::make_tuple(texture.source, wrap, alpha_factor, cutoff);
  if (const auto found = textures_.find(key); found != textures_.end()) return found->second;

  const std::string image_name = what + "'s image " + std::to_string(texture.source);
  const std::optional<AlphaImage> image = alpha_image(texture.source, image_name);
  if (!image) return textures_[key] = std::nullopt;
  return textures_[key] = builder_.add_texture(*image, wrap, alpha_factor, cutoff, image_name);
}

std::optional<AlphaImage> GltfAlphaMasks::alpha_image(int image_index, const std::string& what) {
  const tinygltf::Image& image = model_.images[std::size_t(image_index)];
  if (image.mimeType == "image/jpeg" || (image.bufferView < 0 && cannot_hold_alpha(image.uri)))
    return AlphaImage{};  // no alpha: the material's constant alpha alone cuts
  return alpha_unless_unreadable(
      [&] {
        const std::vector<unsigned char> encoded = encoded_image(image_index, what);
        return decode_alpha(encoded.data(), encoded.size(), path_ + ": " + what);
      },
      warnings_);
}

std::vector<unsigned char> GltfAlphaMasks::encoded_image(int image_index, const std::string& what) const {
  const tinygltf::Image& image = model_.images[std::size_t(image_index)];
  if (image.bufferView >= 0) return accessors_.view_bytes(image.bufferView, what);
  if (image.uri.empty()) return image.image;  // a data URI, kept by keep_data_uri_images
  return read_regular_file(find_texture_file(base_dir_, percent_decoded(image.uri)), path_ + ": " + what);
}

}  // namespace mbao
