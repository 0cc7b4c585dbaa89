// The G-buffer's plane sets (kernels/mbao/gbuffer.h): each screen-space pass
// reads only planes that the set written for it holds, a G-buffer holds its
// set's planes and no room for others, and a store writes the planes its set
// names and nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "mbao/gbuffer.h"
#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

const struct {
  const char* name;
  int plane;
} kPlaneNames[] = {{"GBUFFER_X", GBUFFER_X},
                   {"GBUFFER_Y", GBUFFER_Y},
                   {"GBUFFER_Z", GBUFFER_Z},
                   {"GBUFFER_T", GBUFFER_T},
                   {"GBUFFER_NX", GBUFFER_NX},
                   {"GBUFFER_NY", GBUFFER_NY},
                   {"GBUFFER_NZ", GBUFFER_NZ},
                   {"GBUFFER_FOOTPRINT", GBUFFER_FOOTPRINT},
                   {"GBUFFER_DEPTH", GBUFFER_DEPTH},
                   {"GBUFFER_SX", GBUFFER_SX},
                   {"GBUFFER_SY", GBUFFER_SY},
                   {"GBUFFER_SZ", GBUFFER_SZ},
                   {"GBUFFER_TRIANGLE", GBUFFER_TRIANGLE}};
static_assert(std::size(kPlaneNames) == GBUFFER_PLANES);

// The planes a program's text names, as a mask.
mbao_u32 planes_read_by(const std::string& program) {
  const std::string text(embedded_kernel_files().at(program));
  const std::regex plane_name("GBUFFER_[A-Z]+\\b");
  mbao_u32 planes = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), plane_name); it != std::sregex_iterator(); ++it)
    for (const auto& named : kPlaneNames)
      if (it->str() == named.name) planes |= MBAO_GBUFFER_PLANE(named.plane);
  return planes;
}

TEST(GBufferPlanes, EachPassReadsOnlyWhatItsSetHolds) {
  EXPECT_EQ(planes_read_by("hbao.cl"), mbao_u32(MBAO_GBUFFER_HBAO_PLANES));
  EXPECT_EQ(planes_read_by("denoise.cl"), mbao_u32(MBAO_GBUFFER_FILTER_PLANES));
  EXPECT_EQ(planes_read_by("temporal.cl"), mbao_u32(MBAO_GBUFFER_FILTER_PLANES));
  EXPECT_EQ(mbao_u32(MBAO_GBUFFER_ALL_PLANES), (1u << GBUFFER_PLANES) - 1u);
}

TEST(GBufferPlanes, ASetsPlanesLieInPlaneOrderWithNoRoomForOthers) {
  constexpr mbao_u32 kPixels = 5;
  EXPECT_EQ(gbuffer_plane_count(MBAO_GBUFFER_ALL_PLANES), mbao_u32(GBUFFER_PLANES));
  EXPECT_EQ(gbuffer_plane_count(MBAO_GBUFFER_HBAO_PLANES), 4u);
  EXPECT_EQ(gbuffer_plane_count(MBAO_GBUFFER_FILTER_PLANES), 8u);
  for (int plane = 0; plane < GBUFFER_PLANES; ++plane)  // the whole G-buffer, as mbao.gbuffer returns it
    EXPECT_EQ(gbuffer_plane_offset(kPixels, MBAO_GBUFFER_ALL_PLANES, GBufferPlane(plane)), mbao_u64(plane) * kPixels);
  const GBufferPlane hbao[] = {GBUFFER_DEPTH, GBUFFER_SX, GBUFFER_SY, GBUFFER_SZ};
  for (mbao_u64 slot = 0; slot < std::size(hbao); ++slot)
    EXPECT_EQ(gbuffer_plane_offset(kPixels, MBAO_GBUFFER_HBAO_PLANES, hbao[slot]), slot * kPixels) << hbao[slot];
}

TEST(GBufferPlanes, AStoreWritesTheNamedPlanesAndNothingElse) {
  constexpr mbao_u32 kPixels = 3, kPixel = 1;
  const GBufferTexel texel = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13};
  for (const mbao_u32 set : {mbao_u32(MBAO_GBUFFER_HBAO_PLANES), mbao_u32(MBAO_GBUFFER_FILTER_PLANES),
                             mbao_u32(MBAO_GBUFFER_ALL_PLANES), 0u}) {
    // Room for every plane, so that a store past the set's shows.
    std::vector<float> planes(GBUFFER_PLANES * kPixels, NAN);
    gbuffer_store(planes.data(), kPixels, kPixel, texel, set);
    std::size_t stored = 0;
    for (int plane = 0; plane < GBUFFER_PLANES; ++plane) {
      if (!(set & MBAO_GBUFFER_PLANE(plane))) continue;
      EXPECT_EQ(gbuffer_plane(planes.data(), kPixels, set, GBufferPlane(plane))[kPixel],
                plane == GBUFFER_TRIANGLE ? mbao_u32_as_float(13) : float(plane + 1))
          << "plane " << plane << " of set " << set;
      ++stored;
    }
    const auto written = std::count_if(planes.begin(), planes.end(), [](float v) { return !std::isnan(v); });
    EXPECT_EQ(std::size_t(written), stored) << "set " << set;
  }
}

}  // namespace
}  // namespace mbao
