#pragma once

// Settings as the Python API and the command line name them: one definition
// of each setting's name, group, kind, default, range and meaning, in a table
// per settings struct (the render's, HBAO's, the denoiser's, temporal
// accumulation's and the bake's own). The bindings set the structs from them and take their
// docstrings and signatures from them. mbao.render takes its signature and
// docstring from the render's, mbao.Engine its fields, and `python -m mbao
// render` its options from the render's and HBAO's. Each struct's validate
// checks the ranges given here.

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "bake/bake_settings.h"
#include "render/render_settings.h"

namespace mbao {

// Render settings decide the image; engine settings decide how the work is done, never the image.
enum class SettingGroup { Render, Engine };

// Integer: a 64-bit integer in [lo, hi]. Unsigned: an unsigned 64-bit one in [lo, hi].
// AutoCount: a count >= 1, or 0 for mbao's choice (None in Python). Real: a number
// in [lo, hi], lo itself refused where lo_open and hi where hi_open; unset (None)
// where none_means says what that stands for. Choice: one of `choices`. Flag: a bool.
enum class SettingKind { Integer, Unsigned, AutoCount, Real, Choice, Flag };

// std::monostate: an optional setting left unset.
using SettingValue = std::variant<std::monostate, std::int64_t, std::uint64_t, double, std::string, bool>;

// What values a setting takes, whatever struct holds it.
struct SettingRange {
  SettingKind kind = SettingKind::Flag;
  SettingValue lo{}, hi{};                // Integer, Unsigned, Real
  bool lo_open = false, hi_open = false;  // Real
  std::vector<std::string> choices;       // Choice

  // The allowed values as the errors and the docs state them: "[1, 16384]", "> 0", "[0, 2^64)", ...
  std::string range() const;
  // Throws std::invalid_argument "NAME must be in RANGE, got VALUE" where `value` lies outside it.
  void check(const std::string& name, const SettingValue& value) const;
};

// One setting of a `Settings` struct.
template <typename Settings>
struct SettingSpecOf : SettingRange {
  std::string name;  // the Python keyword; the command line's option is --name with '-' for '_'
  SettingGroup group = SettingGroup::Render;
  std::string doc;         // what it means, a sentence or two
  std::string none_means;  // Real: what leaving it unset stands for; empty where it must be set
  std::function<SettingValue(const Settings&)> get;
  std::function<void(Settings&, const SettingValue&)> set;  // Choice: throws std::invalid_argument for a bad name

  SettingValue default_value() const { return get(Settings{}); }
  // Throws as SettingRange::check where `settings` holds a value outside the range.
  void check(const Settings& settings) const { SettingRange::check(name, get(settings)); }
};

using SettingSpec = SettingSpecOf<RenderSettings>;

// The setting `name` of a table; throws std::invalid_argument naming the table and listing its settings
// where there is none of that name.
template <typename Settings>
const SettingSpecOf<Settings>& setting_spec_in(const std::vector<SettingSpecOf<Settings>>& specs,
                                               const std::string& table, const std::string& name) {
  std::string names;
  for (const SettingSpecOf<Settings>& spec : specs) {
    if (spec.name == name) return spec;
    names += (names.empty() ? "" : ", ") + spec.name;
  }
  throw std::invalid_argument("no " + table + " setting \"" + name + "\"; the settings are " + names);
}

// Every render setting, in the order the docs list them: the render group first.
const std::vector<SettingSpec>& setting_specs();
// Throws std::invalid_argument listing the settings where there is none of that name.
const SettingSpec& setting_spec(const std::string& name);

// HBAO's, the denoiser's and temporal accumulation's settings, in their constructors' order.
const std::vector<SettingSpecOf<HbaoSettings>>& hbao_setting_specs();
const std::vector<SettingSpecOf<DenoiseSettings>>& denoise_setting_specs();
const std::vector<SettingSpecOf<TemporalSettings>>& temporal_setting_specs();
// mbao.bake's own settings (bake/bake_settings.h), in its signature's order.
const std::vector<SettingSpecOf<BakeSettings>>& bake_setting_specs();

}  // namespace mbao
