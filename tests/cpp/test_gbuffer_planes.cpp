// The G-buffer's plane sets (kernels/mbao/gbuffer.h): each screen-space pass
// reads only planes that the set written for it holds, and a store writes the
// planes its set names and nothing else.
#include <gtest/gtest.h>

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
} kPlaneNames[] = {{"GBUFFER_X", GBUFFER_X},         {"GBUFFER_Y", GBUFFER_Y},         {"GBUFFER_Z", GBUFFER_Z},
                   {"GBUFFER_T", GBUFFER_T},         {"GBUFFER_NX", GBUFFER_NX},       {"GBUFFER_NY", GBUFFER_NY},
                   {"GBUFFER_NZ", GBUFFER_NZ},       {"GBUFFER_FOOTPRINT", GBUFFER_FOOTPRINT},
                   {"GBUFFER_DEPTH", GBUFFER_DEPTH}, {"GBUFFER_SX", GBUFFER_SX},       {"GBUFFER_SY", GBUFFER_SY},
                   {"GBUFFER_SZ", GBUFFER_SZ},       {"GBUFFER_TRIANGLE", GBUFFER_TRIANGLE}};
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

TEST(GBufferPlanes, AStoreWritesTheNamedPlanesAndLeavesTheOthers) {
  constexpr mbao_u32 kPixels = 3, kPixel = 1;
  const GBufferTexel texel = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13};
  for (const mbao_u32 set : {mbao_u32(MBAO_GBUFFER_HBAO_PLANES), mbao_u32(MBAO_GBUFFER_FILTER_PLANES),
                             mbao_u32(MBAO_GBUFFER_ALL_PLANES), 0u}) {
    std::vector<float> planes(GBUFFER_PLANES * kPixels, NAN);
    gbuffer_store(planes.data(), kPixels, kPixel, texel, set);
    for (int plane = 0; plane < GBUFFER_PLANES; ++plane) {
      const float stored = planes[plane * kPixels + kPixel];
      if (set & MBAO_GBUFFER_PLANE(plane))
        EXPECT_EQ(stored, plane == GBUFFER_TRIANGLE ? mbao_u32_as_float(13) : float(plane + 1)) << plane;
      else
        EXPECT_TRUE(std::isnan(stored)) << "plane " << plane << " of set " << set;
      EXPECT_TRUE(std::isnan(planes[plane * kPixels])) << "another pixel, plane " << plane;
    }
  }
}

}  // namespace
}  // namespace mbao
