// The settings' table (render/setting_specs.h): what the Python API, its
// docstring and the command line take names, defaults and ranges from.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "render/setting_specs.h"

namespace mbao {
namespace {

std::string refusal(const SettingSpec& spec, const SettingValue& value) {
  RenderSettings s;
  spec.set(s, value);
  try {
    spec.check(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// A table of distinct names, each documented, whose defaults lie inside
// their ranges and read back as set, and make a valid struct together.
template <typename Settings>
void expect_a_table_of_its_struct(const std::vector<SettingSpecOf<Settings>>& specs) {
  std::set<std::string> names;
  for (const SettingSpecOf<Settings>& spec : specs) {
    SCOPED_TRACE(spec.name);
    EXPECT_TRUE(names.insert(spec.name).second);
    EXPECT_FALSE(spec.doc.empty());
    EXPECT_NO_THROW(spec.check(Settings{}));
    Settings s;
    spec.set(s, spec.default_value());
    EXPECT_EQ(spec.get(s), spec.default_value());
  }
  Settings{}.validate();
}

TEST(SettingSpecs, EveryDefaultIsInsideItsRangeAndReadsBackAsSet) { expect_a_table_of_its_struct(setting_specs()); }

TEST(SettingSpecs, RangesAreCheckedAndStated) {
  EXPECT_EQ(setting_spec("width").range(), "[1, 16384]");
  EXPECT_EQ(refusal(setting_spec("width"), std::int64_t(0)), "width must be in [1, 16384], got 0");
  EXPECT_EQ(refusal(setting_spec("width"), std::int64_t(16384)), "");
  EXPECT_EQ(setting_spec("seed").range(), "[0, 2^64)");
  EXPECT_EQ(refusal(setting_spec("max_rays"), std::uint64_t(0)), "max_rays must be in [1, 2^64), got 0");
  EXPECT_EQ(setting_spec("rho").range(), "[0, 1]");
  EXPECT_NE(refusal(setting_spec("rho"), double(NAN)).find("rho must be in [0, 1]"), std::string::npos);
  EXPECT_EQ(setting_spec("max_distance").range(), "> 0");
  EXPECT_NE(refusal(setting_spec("max_distance"), 0.0).find("max_distance must be > 0"), std::string::npos);
  EXPECT_EQ(refusal(setting_spec("max_distance"), double(INFINITY)), "");
  EXPECT_EQ(setting_spec("estimator").range(), "\"branching\" or \"path\"");
}

TEST(SettingSpecs, ChoicesAreTheNamesTheSettingsTake) {
  for (const SettingSpec& spec : setting_specs()) {
    if (spec.kind != SettingKind::Choice) continue;
    SCOPED_TRACE(spec.name);
    for (const std::string& name : spec.choices) {
      RenderSettings s;
      spec.set(s, name);
      EXPECT_EQ(std::get<std::string>(spec.get(s)), name);
    }
    RenderSettings s;
    EXPECT_THROW(spec.set(s, std::string("no such")), std::invalid_argument);
  }
}

TEST(SettingSpecs, AnUnknownNameListsTheSettings) {
  try {
    setting_spec("witdh");
    FAIL() << "an unknown setting was found";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("\"witdh\""), std::string::npos);
    EXPECT_NE(message.find("width, height, bounces"), std::string::npos);
  }
}

TEST(SettingSpecs, EngineSettingsAreTheOnesThatCannotChangeTheImage) {
  std::set<std::string> engine;
  for (const SettingSpec& spec : setting_specs())
    if (spec.group == SettingGroup::Engine) engine.insert(spec.name);
  EXPECT_EQ(engine,
            (std::set<std::string>{"traversal", "organisation", "tile_pixels", "work_group_size", "traversal_stats"}));
}

template <typename Settings>
std::string struct_refusal(const std::vector<SettingSpecOf<Settings>>& specs, const std::string& name,
                           const SettingValue& value) {
  Settings s;
  for (const SettingSpecOf<Settings>& spec : specs)
    if (spec.name == name) spec.set(s, value);
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// HBAO's, the denoiser's and temporal accumulation's tables, and each
// struct's validate refusing what its table does, naming the struct.
TEST(SettingSpecs, EachFilterAndHbaoSettingIsInItsTable) {
  expect_a_table_of_its_struct(hbao_setting_specs());
  expect_a_table_of_its_struct(denoise_setting_specs());
  expect_a_table_of_its_struct(temporal_setting_specs());
  const auto& hbao = hbao_setting_specs();
  EXPECT_EQ(struct_refusal(hbao, "directions", std::int64_t(0)), "hbao directions must be in [1, 64], got 0");
  EXPECT_NE(struct_refusal(hbao, "angle_bias_deg", 90.0).find("hbao angle_bias_deg must be in [0, 90), got 90"),
            std::string::npos);
  EXPECT_EQ(struct_refusal(hbao, "angle_bias_deg", 89.5), "");
  const auto& denoise = denoise_setting_specs();
  EXPECT_NE(struct_refusal(denoise, "sigma_value", double(INFINITY)).find("denoise sigma_value must be in (0, inf)"),
            std::string::npos);
  EXPECT_NE(struct_refusal(denoise, "sigma_plane", 0.0).find("denoise sigma_plane must be in (0, inf)"),
            std::string::npos);
  EXPECT_EQ(struct_refusal(temporal_setting_specs(), "max_length", std::int64_t(65537)),
            "temporal max_length must be in [1, 65536], got 65537");
}

// The bake's own table (mbao.bake, `python -m mbao bake`): its checks are
// the core's, whether the bake comes from Python or from C++.
TEST(SettingSpecs, TheBakesOwnSettingsAreInTheirTable) {
  expect_a_table_of_its_struct(bake_setting_specs());
  const auto& bake = bake_setting_specs();
  EXPECT_EQ(struct_refusal(bake, "samples", std::int64_t(1)), "samples must be in [2, 65536], got 1");
  EXPECT_EQ(struct_refusal(bake, "padding", std::int64_t(65)), "padding must be in [0, 64], got 65");
  EXPECT_EQ(struct_refusal(bake, "directions", std::int64_t(0)), "directions must be in [1, 1048576], got 0");
  EXPECT_EQ(struct_refusal(bake, "estimator", std::string("branching")), "");
  BakeSettings s;
  EXPECT_THROW(bake[0].set(s, std::string("faces")), std::invalid_argument);  // target: "vertices" or "texture"
  EXPECT_EQ(s.target, "vertices");
}

}  // namespace
}  // namespace mbao
