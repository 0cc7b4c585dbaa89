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

TEST(SettingSpecs, EveryDefaultIsInsideItsRangeAndReadsBackAsSet) {
  std::set<std::string> names;
  for (const SettingSpec& spec : setting_specs()) {
    SCOPED_TRACE(spec.name);
    EXPECT_TRUE(names.insert(spec.name).second);
    EXPECT_FALSE(spec.doc.empty());
    EXPECT_NO_THROW(spec.check(RenderSettings{}));
    RenderSettings s;
    spec.set(s, spec.default_value());
    EXPECT_EQ(spec.get(s), spec.default_value());
  }
  RenderSettings defaults;
  defaults.validate();  // the defaults together make a render
}

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
  EXPECT_EQ(engine, (std::set<std::string>{"traversal", "organisation", "tile_pixels", "work_group_size",
                                           "traversal_stats"}));
}

}  // namespace
}  // namespace mbao
