// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "pipeline/method.h"
#include "pipeline/settings.h"

namespace omnislice {

// Every listed setting can be set back from its own text: --set and headers round-trip.
TEST(Settings, ListRoundTrips) {
  Settings s;
  ASSERT_TRUE(setSetting(s, "layer_height", "0.15").ok());
  ASSERT_TRUE(setSetting(s, "walls", "3").ok());
  ASSERT_TRUE(setSetting(s, "infill_pattern", "lines").ok());
  ASSERT_TRUE(setSetting(s, "direction", "0,1,1").ok());
  ASSERT_TRUE(setSetting(s, "up", "-y").ok());
  const auto listed = listSettings(s);
  Settings t;
  for (const auto& [k, v] : listed) {
    Outcome o = setSetting(t, k, v);
    EXPECT_TRUE(o.ok()) << k << " = " << v << ": " << o.message;
  }
  EXPECT_EQ(listSettings(t), listed);
  EXPECT_DOUBLE_EQ(t.layerHeight, 0.15);
  EXPECT_EQ(t.walls, 3);
  // Set from its listing (10 significant digits), the normalised direction is kept as listed.
  EXPECT_NEAR(s.direction.norm(), 1.0, 1e-15);
  EXPECT_NEAR(t.direction.norm(), 1.0, 1e-9);
  EXPECT_EQ(t.direction.y(), 0.7071067812);
  EXPECT_EQ(t.placement.up, UpAxis::NegY);
}

// Bad values name the key and never change the setting.
TEST(Settings, RejectsAbsurdValues) {
  Settings s;
  const Settings before = s;
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{
           {"layer_height", "-1"}, {"layer_height", "nan"}, {"layer_height", "inf"},
           {"layer_height", "0.2mm"}, {"walls", "2.5"}, {"walls", "-1"}, {"infill", "101"},
           {"direction", "0,0,0"}, {"direction", "1,2"}, {"up", "w"}, {"nope", "1"},
           {"method", "magic"}, {"scale", "0"}, {"center", "maybe"}}) {
    Outcome o = setSetting(s, k, v);
    EXPECT_EQ(o.status, Status::InvalidOption) << k << "=" << v;
    EXPECT_NE(o.message.find(k == "nope" ? "nope" : k), std::string::npos) << o.message;
  }
  EXPECT_EQ(listSettings(s), listSettings(before));
}

// Cross-field checks: a layer thicker than the nozzle cannot be printed.
TEST(Settings, ValidateCrossFields) {
  Settings s;
  EXPECT_TRUE(validateSettings(s).ok());
  ASSERT_TRUE(setSetting(s, "layer_height", "0.6").ok());
  EXPECT_EQ(validateSettings(s).status, Status::InvalidOption);
  ASSERT_TRUE(setSetting(s, "nozzle", "0.8").ok());
  EXPECT_TRUE(validateSettings(s).ok());
}

// The table (settings_table.cpp) is the one declaration: every key once; every setting's default,
// formatted, parses back to the same text; numbers at both ends of their range parse and just
// outside them are refused; every choice parses and is listed as written; the listing follows the
// table's order and leaves out what is not listed (machine_json) or belongs to another method.
TEST(SettingsTable, EveryEntryParsesItsDefaultItsRangeAndItsChoices) {
  std::set<std::string> keys;
  const Settings defaults;
  for (const SettingSpec& spec : settingSpecs()) {
    EXPECT_TRUE(keys.insert(spec.key).second) << "duplicate key " << spec.key;
    EXPECT_EQ(findSetting(spec.key), &spec);
    Settings s;
    const std::string text = spec.format(defaults);
    Outcome o = spec.parse(s, text);
    EXPECT_TRUE(o.ok()) << spec.key << " = '" << text << "': " << o.message;
    EXPECT_EQ(spec.format(s), text) << spec.key;
    if (spec.type == SettingType::Number || spec.type == SettingType::Integer) {
      ASSERT_LT(spec.min, spec.max) << spec.key;
      for (double v : {spec.min, spec.max}) {
        Settings t;
        EXPECT_TRUE(setSetting(t, spec.key, formatSettingNumber(v)).ok()) << spec.key << " = " << v;
        EXPECT_DOUBLE_EQ(std::stod(spec.format(t)), v) << spec.key;
      }
      const double below = spec.min - std::max(1.0, std::abs(spec.min)), above = spec.max + std::max(1.0, spec.max);
      for (double v : {below, above}) {
        Settings t;
        const Outcome bad = setSetting(t, spec.key, formatSettingNumber(v));
        EXPECT_EQ(bad.status, Status::InvalidOption) << spec.key << " = " << v;
        EXPECT_NE(bad.message.find(spec.key), std::string::npos) << bad.message;
        EXPECT_EQ(spec.format(t), text) << spec.key << ": a refused value changed the setting";
      }
    }
    if (spec.type == SettingType::Choice || spec.type == SettingType::Boolean) {
      ASSERT_FALSE(spec.choices.empty()) << spec.key;
      for (const std::string& c : spec.choices) {
        Settings t;
        EXPECT_TRUE(setSetting(t, spec.key, c).ok()) << spec.key << " = " << c;
        EXPECT_EQ(spec.format(t), c) << spec.key;
      }
      Settings t;
      EXPECT_EQ(setSetting(t, spec.key, "no-such-value").status, Status::InvalidOption) << spec.key;
    }
  }
  // The listing is the table's order, filtered.
  for (Method m : {Method::Planar, Method::Voxel, Method::Multidir, Method::Geodesic, Method::Surface}) {
    Settings s;
    s.method = m;
    const auto listed = listSettings(s);
    size_t i = 0;
    for (const SettingSpec& spec : settingSpecs()) {
      const bool shown = spec.listed && (!spec.onlyFor || *spec.onlyFor == m);
      if (!shown) continue;
      ASSERT_LT(i, listed.size());
      EXPECT_EQ(listed[i].first, spec.key);
      ++i;
    }
    EXPECT_EQ(i, listed.size());
    for (const auto& [k, v] : listed) EXPECT_NE(k, "machine_json");
  }
}

// The schema the page and `omnislice settings --schema` read: every table entry, in order, with
// its default as listed, its range and its choices.
TEST(SettingsTable, SchemaJsonHoldsTheTable) {
  const nlohmann::json schema = nlohmann::json::parse(settingsSchemaJson());
  ASSERT_TRUE(schema.is_array());
  ASSERT_EQ(schema.size(), settingSpecs().size());
  const Settings defaults;
  for (size_t i = 0; i < schema.size(); ++i) {
    const SettingSpec& spec = settingSpecs()[i];
    const nlohmann::json& j = schema[i];
    EXPECT_EQ(j["key"], spec.key);
    EXPECT_EQ(j["default"], spec.format(defaults));
    EXPECT_EQ(j["unit"], spec.unit);
    if (spec.type == SettingType::Number || spec.type == SettingType::Integer) {
      EXPECT_EQ(j["min"].get<double>(), spec.min);
      EXPECT_EQ(j["max"].get<double>(), spec.max);
    } else {
      EXPECT_FALSE(j.contains("min")) << spec.key;
    }
    if (spec.type == SettingType::Choice) {
      EXPECT_EQ(j["choices"].get<std::vector<std::string>>(), spec.choices);
    }
    EXPECT_EQ(j.contains("method"), spec.onlyFor.has_value()) << spec.key;
  }
  // Aliases resolve to their setting; unknown keys are refused by name.
  EXPECT_EQ(findSetting("nozzle"), findSetting("nozzle_diameter"));
  EXPECT_EQ(findSetting("placement.up"), findSetting("up"));
  EXPECT_EQ(findSetting("voxel.width"), findSetting("voxel.width_mm"));
  EXPECT_EQ(findSetting("layer-height"), findSetting("layer_height"));
  EXPECT_EQ(findSetting("nope"), nullptr);
}

// Every method is registered once, by its name, with the machines it prints on.
TEST(MethodRegistry, EveryMethodOnceByName) {
  std::set<std::string> names;
  for (const MethodEntry& e : methodRegistry()) {
    EXPECT_TRUE(names.insert(methodName(e.method)).second);
    EXPECT_EQ(&methodEntry(e.method), &e);
    Method back = Method::Planar;
    ASSERT_TRUE(parseMethod(methodName(e.method), back));
    EXPECT_EQ(back, e.method);
    EXPECT_FALSE(e.machines.empty());
    EXPECT_NE(e.run, nullptr);
    // A method that refuses a machine kind says why and what to choose.
    if (e.machines.size() < 4) {
      EXPECT_NE(std::string(e.machineNeed).find("choose"), std::string::npos);
    }
  }
  EXPECT_EQ(names.size(), 5u);
  Method m = Method::Planar;
  EXPECT_FALSE(parseMethod("magic", m));
}

}  // namespace omnislice
