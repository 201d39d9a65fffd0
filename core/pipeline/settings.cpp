// SPDX-License-Identifier: MIT
// The settings API over the table (settings_table.cpp): set by key, check, list, schema.
#include "pipeline/settings.h"

#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace omnislice {

namespace {

// Accepted aliases (CLI spellings) -> canonical key.
std::string canonicalKey(std::string key) {
  for (char& c : key) {
    if (c == '-') c = '_';
  }
  static const std::map<std::string, std::string> aliases = {
      {"nozzle", "nozzle_diameter"}, {"infill_percent", "infill"}, {"infill_density", "infill"},
      {"placement.scale", "scale"},  {"placement.fit_mm", "fit_mm"}, {"placement.up", "up"},
      {"placement.center", "center"}, {"placement.rotate_x_deg", "rotate_x_deg"},
      {"placement.rotate_y_deg", "rotate_y_deg"}, {"placement.rotate_z_deg", "rotate_z_deg"},
      {"perimeters", "walls"},       {"direction_d", "direction"},
      {"gcode_dialect", "gcode_flavor"}, {"flavor", "gcode_flavor"},
      {"free_rotation_samples", "motion.free_rotation_samples"},
      {"voxel.width", "voxel.width_mm"}, {"voxel.shadow_scheme", "voxel.shadow"},
      {"voxel.platform_radius", "voxel.platform_radius_mm"},
  };
  auto it = aliases.find(key);
  return it == aliases.end() ? key : it->second;
}

const char* typeName(SettingType t) {
  switch (t) {
    case SettingType::Number: return "number";
    case SettingType::Integer: return "integer";
    case SettingType::Boolean: return "boolean";
    case SettingType::Choice: return "choice";
    case SettingType::Vector: return "vector";
    case SettingType::Text: return "text";
  }
  return "text";
}

}  // namespace

std::string formatSettingNumber(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string formatSettingVector(const Eigen::Vector3d& v) {
  return formatSettingNumber(v.x()) + "," + formatSettingNumber(v.y()) + "," + formatSettingNumber(v.z());
}

const SettingSpec* findSetting(const std::string& rawKey) {
  static const std::map<std::string, const SettingSpec*> byKey = [] {
    std::map<std::string, const SettingSpec*> m;
    for (const SettingSpec& s : settingSpecs()) m[s.key] = &s;
    return m;
  }();
  auto it = byKey.find(canonicalKey(rawKey));
  return it == byKey.end() ? nullptr : it->second;
}

Outcome setSetting(Settings& settings, const std::string& key, const std::string& value) {
  const SettingSpec* spec = findSetting(key);
  if (spec == nullptr) return {Status::InvalidOption, "unknown setting '" + key + "'"};
  return spec->parse(settings, value);
}

Outcome validateSettings(const Settings& s) {
  if (s.layerHeight > s.nozzleDiameter) {
    return {Status::InvalidOption, "setting 'layer_height': " + formatSettingNumber(s.layerHeight) +
                                       " mm is thicker than the nozzle (" +
                                       formatSettingNumber(s.nozzleDiameter) + " mm)"};
  }
  if (s.effectiveFirstLayerHeight() > s.nozzleDiameter) {
    return {Status::InvalidOption, "setting 'first_layer_height' is thicker than the nozzle"};
  }
  const double w = s.effectiveLineWidth();
  if (w < 0.5 * s.nozzleDiameter || w > 3 * s.nozzleDiameter) {
    return {Status::InvalidOption, "setting 'line_width': " + formatSettingNumber(w) +
                                       " mm must be between 0.5x and 3x the nozzle diameter"};
  }
  if (w < s.layerHeight) {
    return {Status::InvalidOption, "setting 'line_width' must not be smaller than the layer height"};
  }
  if (s.isoplanar.thetaDegrees >= 180) {
    return {Status::InvalidOption, "setting 'isoplanar.theta_deg': drive-plane angles are in [0, 180) "
                                   "(theta and theta + 180 give the same planes), or -1 to search"};
  }
  if (s.isoplanar.thetaDegrees < 0 && s.isoplanar.thetaDegrees != -1) {
    return {Status::InvalidOption, "setting 'isoplanar.theta_deg': use an angle in [0, 180) or -1 to search"};
  }
  if (s.axisFreedomDegrees < 0 && s.axisFreedomDegrees != -1) {
    return {Status::InvalidOption,
            "setting 'motion.axis_freedom_deg': use an angle in [0, 45] or -1 for the method's (geodesic 25, voxel 15)"};
  }
  if (s.fill == FillMode::Spiral && s.method != Method::Voxel) {
    return {Status::InvalidOption, "setting 'fill': spiral fills curved layers of method voxel only"};
  }
  return {};
}

std::vector<std::pair<std::string, std::string>> listSettings(const Settings& s) {
  // Resolved values (line width, first layer) so a header states what was printed.
  Settings copy = s;
  copy.lineWidth = s.effectiveLineWidth();
  copy.firstLayerHeight = s.effectiveFirstLayerHeight();
  copy.axisFreedomDegrees = s.effectiveAxisFreedom();
  std::vector<std::pair<std::string, std::string>> out;
  for (const SettingSpec& spec : settingSpecs()) {
    if (!spec.listed || (spec.onlyFor && *spec.onlyFor != s.method)) continue;
    out.emplace_back(spec.key, spec.format(copy));
  }
  return out;
}

std::string settingsSchemaJson() {
  const Settings defaults;
  nlohmann::ordered_json all = nlohmann::ordered_json::array();
  for (const SettingSpec& spec : settingSpecs()) {
    nlohmann::ordered_json j;
    j["key"] = spec.key;
    j["type"] = typeName(spec.type);
    j["default"] = spec.format(defaults);
    if (spec.type == SettingType::Number || spec.type == SettingType::Integer) {
      j["min"] = spec.min;
      j["max"] = spec.max;
    }
    j["unit"] = spec.unit;
    j["help"] = spec.help;
    if (spec.type == SettingType::Choice || spec.type == SettingType::Boolean) j["choices"] = spec.choices;
    if (spec.onlyFor) j["method"] = methodName(*spec.onlyFor);
    all.push_back(j);
  }
  return all.dump();
}

PlanarOptions planarOptions(const Settings& s) {
  PlanarOptions o;
  o.lineWidth = s.effectiveLineWidth();
  o.filamentDiameter = s.filamentDiameter;
  o.walls = s.walls;
  o.topLayers = s.topLayers;
  o.bottomLayers = s.bottomLayers;
  o.infillPercent = s.infillPercent;
  o.infillPattern = s.infillPattern;
  o.seam = s.seam;
  o.infillAngleDegrees = s.infillAngleDegrees;
  o.infillOverlapPercent = s.infillOverlapPercent;
  o.allLinesAlongInfillAngle = s.fill == FillMode::Isoplanar;
  o.printSpeed = s.printSpeed;
  o.outerWallSpeed = s.outerWallSpeed;
  o.infillSpeed = s.infillSpeed;
  o.firstLayerSpeed = s.firstLayerSpeed;
  o.travelSpeed = s.travelSpeed;
  o.retractLength = s.retractLength;
  o.retractSpeed = s.retractSpeed;
  o.retractMinTravel = s.retractMinTravel;
  o.travelInside = s.travelInside;
  o.bridges = s.bridges;
  o.gapFill = s.gapFill;
  o.bridgeSpeed = s.bridgeSpeed;
  o.bridgeFlowPercent = s.bridgeFlowPercent;
  o.retractInsideMaxTravel = s.retractInsideMaxTravel;
  return o;
}

}  // namespace omnislice
