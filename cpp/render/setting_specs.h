#pragma once

// The render settings as the Python API and the command line name them: one
// definition of each setting's name, group, kind, default, range and meaning.
// The binding sets RenderSettings from them. mbao.render takes its signature
// and docstring from them, mbao.Engine its fields, and `python -m mbao render`
// its options. RenderSettings::validate checks the ranges given here.

#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "render/render_settings.h"

namespace mbao {

// Render settings decide the image; engine settings decide how the work is done, never the image.
enum class SettingGroup { Render, Engine };

// Integer: a 64-bit integer in [lo, hi]. Unsigned: an unsigned 64-bit one in [lo, hi].
// AutoCount: a count >= 1, or 0 for mbao's choice (None in Python). Real: a number
// in [lo, hi], lo itself refused where lo_open; unset (None) where none_means says
// what that stands for. Choice: one of `choices`. Flag: a bool.
enum class SettingKind { Integer, Unsigned, AutoCount, Real, Choice, Flag };

// std::monostate: an optional setting left unset.
using SettingValue = std::variant<std::monostate, std::int64_t, std::uint64_t, double, std::string, bool>;

struct SettingSpec {
  std::string name;  // the Python keyword; the command line's option is --name with '-' for '_'
  SettingGroup group;
  SettingKind kind;
  std::string doc;  // what it means, a sentence or two
  SettingValue lo{}, hi{};  // Integer, Unsigned, Real
  bool lo_open = false;     // Real
  std::string none_means;   // Real: what leaving it unset stands for; empty where it must be set
  std::vector<std::string> choices;  // Choice
  std::function<SettingValue(const RenderSettings&)> get;
  std::function<void(RenderSettings&, const SettingValue&)> set;  // Choice: throws std::invalid_argument for a bad name

  SettingValue default_value() const { return get(RenderSettings{}); }
  // The allowed values as the errors and the docs state them: "[1, 16384]", "> 0", "[0, 2^64)", ...
  std::string range() const;
  // Throws std::invalid_argument "NAME must be in RANGE, got VALUE" where `settings` holds a value outside it.
  void check(const RenderSettings& settings) const;
};

// Every setting, in the order the docs list them: the render group first.
const std::vector<SettingSpec>& setting_specs();
// Throws std::invalid_argument listing the settings where there is none of that name.
const SettingSpec& setting_spec(const std::string& name);

}  // namespace mbao
