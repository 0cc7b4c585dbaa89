// Where a UV set puts a material's triangles in a W x H texture (SPEC 6.3):
// each texel's pieces (a triangle's UV image clipped to the texel), which
// texels are covered and which are claimed twice, and the points of a
// per-texel bake's estimates.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "bake/estimate_points.h"
#include "scene/triangle_mesh.h"
#include "scene/wrap_mode.h"

namespace mbao {

// A texture's sides: it is baked as an image of its own size, which a render's bounds.
constexpr int kMaxTextureSide = 16384;

class TexelLayout : public EstimatePoints {
 public:
  // The triangles `triangles` of `mesh` with texture coordinates `corner_uvs`
  // (three per listed triangle, in its corners' order: a UV seam needs no
  // split vertices) in a width x height texture whose sampler wraps
  // with wrap_s along u and wrap_t along v. Throws std::invalid_argument for
  // a size out of range, UVs that are not finite, or UVs that span more
  // texels than kMaxPieces.
  TexelLayout(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
              const std::vector<glm::vec2>& corner_uvs, int width, int height, WrapMode wrap_s, WrapMode wrap_t);

  int width() const { return width_; }
  int height() const { return height_; }
  // Per texel, row by row: whether pieces of positive area fall in it.
  const std::vector<std::uint8_t>& covered() const { return covered_; }
  std::size_t covered_count() const { return covered_count_; }
  // Covered texels one of whose 4 x 4 sample points lies in two triangles' UV images.
  std::size_t claimed_twice() const { return claimed_twice_; }
  // Positions in the `triangles` given of those that claimed a sample point an
  // earlier one had claimed, in order.
  const std::vector<std::size_t>& second_claimants() const { return second_claimants_; }
  // Triangles of zero UV area: they fall in no texel.
  std::size_t unmapped_triangles() const { return unmapped_; }

  std::size_t targets() const override { return covered_.size(); }
  bool has_surface(std::size_t texel) const override { return covered_[texel] != 0; }
  std::optional<SurfacePoint> point(std::size_t texel, const std::array<double, 4>& random) const override;

  static constexpr std::size_t kMaxPieces = std::size_t(1) << 28;

 private:
  struct Piece {
    std::uint32_t triangle;       // index into triangles_
    std::int32_t cell_x, cell_y;  // the cell of the UV plane (in texels) it was clipped to
    double area_so_far;           // the texel's surface area up to and including this piece
  };
  using Corners = std::array<glm::dvec2, 3>;  // a triangle's UVs in texels
  struct TexelPiece {
    std::uint32_t texel;
    Piece piece;
  };
  void add_pieces(std::uint32_t local, double surface_per_texel, std::vector<TexelPiece>& pieces) const;
  // Returns whether it claimed a point already claimed.
  bool count_claims(std::uint32_t local, std::vector<std::uint16_t>& once, std::vector<std::uint16_t>& twice) const;
  // The texel that cell x of the UV plane falls in along an axis of n texels,
  // and whether it is mirrored; -1 where it falls in none (clamped beyond the edge, for claims only).
  std::int64_t texel_along(std::int64_t cell, int n, WrapMode wrap, bool clamp_beyond, bool* mirrored) const;

  std::vector<std::uint32_t> triangles_;  // the mesh's triangle of each piece's `triangle`
  std::vector<std::size_t> given_at_;     // and its position in the `triangles` given
  std::vector<Corners> corners_;
  int width_, height_;
  WrapMode wrap_s_, wrap_t_;
  std::vector<std::size_t> piece_start_;  // texel i's pieces: pieces_[piece_start_[i], piece_start_[i + 1])
  std::vector<Piece> pieces_;
  std::vector<std::uint8_t> covered_;
  std::size_t covered_count_ = 0, claimed_twice_ = 0, unmapped_ = 0;
  std::vector<std::size_t> second_claimants_;
};

}  // namespace mbao
