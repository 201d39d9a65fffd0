// SPDX-License-Identifier: MIT
#include "pipeline/settings.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>

#include "machine/machine.h"
#include "machine/machine_json.h"

namespace omnislice {

namespace {

Outcome invalid(const std::string& key, const std::string& what) {
  return {Status::InvalidOption, "setting '" + key + "': " + what};
}

// Strict number parse: the whole text must be one finite number.
bool parseNumber(const std::string& text, double& out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || errno == ERANGE) return false;
  while (*end == ' ' || *end == '\t') ++end;
  if (*end != '\0' || !std::isfinite(v)) return false;
  out = v;
  return true;
}

// "x,y,z" (also "x y z" or "[x,y,z]").
bool parseVector(std::string text, Eigen::Vector3d& out) {
  for (char& c : text) {
    if (c == ',' || c == '[' || c == ']' || c == ';') c = ' ';
  }
  std::istringstream in(text);
  std::string a, b, c, extra;
  if (!(in >> a >> b >> c) || (in >> extra)) return false;
  return parseNumber(a, out.x()) && parseNumber(b, out.y()) && parseNumber(c, out.z());
}

bool parseBool(const std::string& text, bool& out) {
  if (text == "true" || text == "1" || text == "yes" || text == "on") return out = true, true;
  if (text == "false" || text == "0" || text == "no" || text == "off") return out = false, true;
  return false;
}

std::string formatNumber(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string formatVector(const Eigen::Vector3d& v) {
  return formatNumber(v.x()) + "," + formatNumber(v.y()) + "," + formatNumber(v.z());
}

const char* upAxisName(UpAxis a) {
  switch (a) {
    case UpAxis::PosZ: return "z";
    case UpAxis::NegZ: return "-z";
    case UpAxis::PosY: return "y";
    case UpAxis::NegY: return "-y";
    case UpAxis::PosX: return "x";
    case UpAxis::NegX: return "-x";
  }
  return "z";
}

// A numeric setting bound to a field with an inclusive range.
struct NumberSpec {
  std::function<double&(Settings&)> field;
  double min, max;
  const char* unit;
};

struct IntSpec {
  std::function<int&(Settings&)> field;
  int min, max;
};

const std::map<std::string, NumberSpec>& numberSpecs() {
  static const std::map<std::string, NumberSpec> specs = {
      {"layer_height", {[](Settings& s) -> double& { return s.layerHeight; }, 0.01, 5, "mm"}},
      {"first_layer_height",
       {[](Settings& s) -> double& { return s.firstLayerHeight; }, 0, 5, "mm (0 = layer_height)"}},
      {"nozzle_diameter", {[](Settings& s) -> double& { return s.nozzleDiameter; }, 0.05, 5, "mm"}},
      {"line_width", {[](Settings& s) -> double& { return s.lineWidth; }, 0, 10, "mm (0 = auto)"}},
      {"filament_diameter",
       {[](Settings& s) -> double& { return s.filamentDiameter; }, 0.5, 5, "mm"}},
      {"infill", {[](Settings& s) -> double& { return s.infillPercent; }, 0, 100, "%"}},
      {"infill_angle_deg",
       {[](Settings& s) -> double& { return s.infillAngleDegrees; }, -360, 360, "degrees"}},
      {"infill_overlap_pct",
       {[](Settings& s) -> double& { return s.infillOverlapPercent; }, 0, 100, "% of line width"}},
      {"print_speed", {[](Settings& s) -> double& { return s.printSpeed; }, 1, 1000, "mm/s"}},
      {"outer_wall_speed", {[](Settings& s) -> double& { return s.outerWallSpeed; }, 1, 1000, "mm/s"}},
      {"infill_speed", {[](Settings& s) -> double& { return s.infillSpeed; }, 1, 1000, "mm/s"}},
      {"first_layer_speed",
       {[](Settings& s) -> double& { return s.firstLayerSpeed; }, 1, 1000, "mm/s"}},
      {"travel_speed", {[](Settings& s) -> double& { return s.travelSpeed; }, 1, 2000, "mm/s"}},
      {"acceleration", {[](Settings& s) -> double& { return s.acceleration; }, 0, 100000, "mm/s^2"}},
      {"retract_length", {[](Settings& s) -> double& { return s.retractLength; }, 0, 20, "mm"}},
      {"retract_speed", {[](Settings& s) -> double& { return s.retractSpeed; }, 1, 200, "mm/s"}},
      {"retract_min_travel",
       {[](Settings& s) -> double& { return s.retractMinTravel; }, 0, 1000, "mm"}},
      {"nozzle_temperature",
       {[](Settings& s) -> double& { return s.nozzleTemperature; }, 0, 500, "deg C (0 = no heating)"}},
      {"bed_temperature",
       {[](Settings& s) -> double& { return s.bedTemperature; }, 0, 200, "deg C (0 = no heating)"}},
      {"scale", {[](Settings& s) -> double& { return s.placement.scale; }, 1e-6, 1e6, "factor"}},
      {"fit_mm", {[](Settings& s) -> double& { return s.placement.fitMm; }, 0, 1e5, "mm (0 = off)"}},
      {"rotate_x_deg",
       {[](Settings& s) -> double& { return s.placement.rotateXDegrees; }, -360, 360, "degrees"}},
      {"rotate_y_deg",
       {[](Settings& s) -> double& { return s.placement.rotateYDegrees; }, -360, 360, "degrees"}},
      {"rotate_z_deg",
       {[](Settings& s) -> double& { return s.placement.rotateZDegrees; }, -360, 360, "degrees"}},
      {"motion.filter_deg",
       {[](Settings& s) -> double& { return s.orientationFilterDegrees; }, 0.1, 180, "degrees"}},
      {"voxel.width_mm",
       {[](Settings& s) -> double& { return s.voxel.widthMm; }, 0, 50, "mm (0 = 0.8 x nozzle)"}},
      {"voxel.peel_step",
       {[](Settings& s) -> double& { return s.voxel.peelStep; }, 0.01, 1000, "peeling sheets"}},
      {"voxel.epsilon",
       {[](Settings& s) -> double& { return s.voxel.epsilon; }, -1, 2, "voxel widths (-1 = default)"}},
      {"voxel.iso_step",
       {[](Settings& s) -> double& { return s.voxel.isoStep; }, 0, 100, "field units (0 = from voxel.layer_mm)"}},
      {"voxel.smooth",
       {[](Settings& s) -> double& { return s.voxel.smoothIterations; }, 0, 200, "smoothing passes"}},
      {"voxel.layer_mm",
       {[](Settings& s) -> double& { return s.voxel.layerMm; }, 0, 5, "mm (0 = voxel width)"}},
      {"voxel.platform_radius_mm",
       {[](Settings& s) -> double& { return s.voxel.platformRadiusMm; }, 0, 5000, "mm (0 = footprint)"}},
      {"voxel.max_tilt_deg",
       {[](Settings& s) -> double& { return s.voxel.maxTiltDegrees; }, 0, 180, "degrees (0 = machine)"}},
      {"isoplanar.theta_deg",
       {[](Settings& s) -> double& { return s.isoplanar.thetaDegrees; }, -1, 180, "degrees, [0, 180) (-1 = search)"}},
      {"isoplanar.directions",
       {[](Settings& s) -> double& { return s.isoplanar.directions; }, 1, 3600, "directions"}},
      {"isoplanar.chord_error_mm",
       {[](Settings& s) -> double& { return s.isoplanar.chordErrorMm; }, 0, 10, "mm (0 = min(0.5, layer height / 8))"}},
      {"isoplanar.stencil_mm",
       {[](Settings& s) -> double& { return s.isoplanar.stencilMm; }, 0.05, 20, "mm"}},
      {"isoplanar.gamma_samples",
       {[](Settings& s) -> double& { return s.isoplanar.gammaSamples; }, 4, 720, "samples"}},
      {"isoplanar.max_feed_mm_s",
       {[](Settings& s) -> double& { return s.isoplanar.maxFeedMmS; }, 0, 2000, "mm/s (0 = print_speed)"}},
      {"surface.base_mm",
       {[](Settings& s) -> double& { return s.surface.baseMm; }, 0.1, 500, "mm"}},
      {"geodesic.interval_mm",
       {[](Settings& s) -> double& { return s.geodesic.intervalMm; }, 0, 20, "mm (0 = layer_height)"}},
      {"geodesic.tet_size_mm",
       {[](Settings& s) -> double& { return s.geodesic.tetSizeMm; }, 0, 100, "mm (0 = from geodesic.target_tets)"}},
      {"geodesic.target_tets",
       {[](Settings& s) -> double& { return s.geodesic.targetTets; }, 100, 3e6, "tets"}},
      {"geodesic.base_band_mm",
       {[](Settings& s) -> double& { return s.geodesic.baseBandMm; }, 0, 20, "mm (heat source: the part within this of the platform; 0 = a quarter interval)"}},
      {"geodesic.max_thickness_ratio",
       {[](Settings& s) -> double& { return s.geodesic.maxThicknessRatio; }, 0, 3, "intervals (largest layer thickness at the surface; 0 = uniform iso-values i d)"}},
      {"geodesic.nozzle_angle_deg",
       {[](Settings& s) -> double& { return s.geodesic.nozzleAngleDeg; }, 0, 89, "degrees (0 = the machine's nozzle cone)"}},
      {"support.sampling_mm",
       {[](Settings& s) -> double& { return s.support.samplingMm; }, 0, 50, "mm (0 = 2.5 x nozzle + 1)"}},
      {"support.angle_deg",
       {[](Settings& s) -> double& { return s.support.angleDeg; }, 0, 89, "degrees (0 = the method's)"}},
      {"support.lambda",
       {[](Settings& s) -> double& { return s.support.lambda; }, 0, 1, "(Eq. 13)"}},
      {"support.merge_angle_deg",
       {[](Settings& s) -> double& { return s.support.mergeAngleDeg; }, 0, 60, "degrees (0 = straight columns)"}},
      {"support.min_diameter_mm",
       {[](Settings& s) -> double& { return s.support.minDiameterMm; }, 0, 20, "mm (0 = 2 x line width)"}},
      {"support.gap_mm",
       {[](Settings& s) -> double& { return s.support.gapMm; }, 0, 5, "mm"}},
      {"multidir.alpha_max_deg",
       {[](Settings& s) -> double& { return s.multidir.alphaMaxDeg; }, 1, 89, "degrees"}},
      {"multidir.w",
       {[](Settings& s) -> double& { return s.multidir.w; }, 1, 1000, "(parts >= V/w)"}},
      {"multidir.offset_step_mm",
       {[](Settings& s) -> double& { return s.multidir.offsetStepMm; }, 0.05, 100, "mm"}},
      {"multidir.platform_margin_mm",
       {[](Settings& s) -> double& { return s.multidir.platformMarginMm; }, 0, 1000, "mm"}},
      {"multidir.max_tilt_deg",
       {[](Settings& s) -> double& { return s.multidir.maxTiltDeg; }, 0, 180, "degrees (0 = machine)"}},
      {"multidir.interface_overlap",
       {[](Settings& s) -> double& { return s.multidir.interfaceOverlap; }, 0, 1,
        "(fraction of the overlap an earlier part may have across a later part's plane)"}},
      {"multidir.step_angle_deg",
       {[](Settings& s) -> double& { return s.multidir.stepAngleDeg; }, 0, 90, "degrees (0 = machine)"}},
      {"voxel.max_voxels",
       {[](Settings& s) -> double& { return s.voxel.maxVoxels; }, 1000, 1e9, "voxels"}},
      {"motion.chord_tolerance",
       {[](Settings& s) -> double& { return s.chordTolerance; }, 0.0001, 1, "mm"}},
  };
  return specs;
}

const std::map<std::string, IntSpec>& intSpecs() {
  static const std::map<std::string, IntSpec> specs = {
      {"walls", {[](Settings& s) -> int& { return s.walls; }, 0, 50}},
      {"top_layers", {[](Settings& s) -> int& { return s.topLayers; }, 0, 200}},
      {"bottom_layers", {[](Settings& s) -> int& { return s.bottomLayers; }, 0, 200}},
      {"motion.free_rotation_samples",
       {[](Settings& s) -> int& { return s.freeRotationSamples; }, 1, 360}},
      {"support.roof_layers", {[](Settings& s) -> int& { return s.support.roofLayers; }, 0, 100}},
      {"multidir.samples", {[](Settings& s) -> int& { return s.multidir.samples; }, 4, 20000}},
      {"multidir.beam_width", {[](Settings& s) -> int& { return s.multidir.beamWidth; }, 1, 100}},
      {"multidir.restarts", {[](Settings& s) -> int& { return s.multidir.restarts; }, 1, 64}},
      {"multidir.perturbations", {[](Settings& s) -> int& { return s.multidir.perturbations; }, 0, 10000}},
      {"multidir.axis_search", {[](Settings& s) -> int& { return s.multidir.axisSearch; }, 0, 3600}},
  };
  return specs;
}

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

}  // namespace

Outcome setSetting(Settings& settings, const std::string& rawKey, const std::string& value) {
  const std::string key = canonicalKey(rawKey);
  if (auto it = numberSpecs().find(key); it != numberSpecs().end()) {
    double v = 0;
    if (!parseNumber(value, v)) return invalid(key, "'" + value + "' is not a finite number");
    if (v < it->second.min || v > it->second.max) {
      return invalid(key, formatNumber(v) + " is outside [" + formatNumber(it->second.min) + ", " +
                              formatNumber(it->second.max) + "] " + it->second.unit);
    }
    it->second.field(settings) = v;
    return {};
  }
  if (auto it = intSpecs().find(key); it != intSpecs().end()) {
    double v = 0;
    if (!parseNumber(value, v) || v != std::floor(v)) {
      return invalid(key, "'" + value + "' is not a whole number");
    }
    if (v < it->second.min || v > it->second.max) {
      return invalid(key, formatNumber(v) + " is outside [" + std::to_string(it->second.min) +
                              ", " + std::to_string(it->second.max) + "]");
    }
    it->second.field(settings) = static_cast<int>(v);
    return {};
  }
  if (key == "method") {
    if (value != "planar" && value != "voxel" && value != "surface" && value != "geodesic" &&
        value != "multidir") {
      return invalid(key, "'" + value +
                              "' is not available in this build (available: planar, voxel, surface, geodesic, "
                              "multidir)");
    }
    settings.method = value;
    return {};
  }
  if (key == "fill") {
    if (value != "auto" && value != "isoplanar" && value != "spiral") {
      return invalid(key, "'" + value + "' is not a fill (auto, isoplanar, spiral)");
    }
    settings.fill = value;
    return {};
  }
  if (key == "geodesic.sequence") {
    std::string v = value;
    for (char& c : v) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (v != "a3" && v != "lpt" && v != "dpt") {
      return invalid(key, "'" + value + "' is not a print sequence (a3, lpt, dpt)");
    }
    settings.geodesic.sequence = v;
    return {};
  }
  if (key == "support") {
    if (value != "auto" && value != "none" && value != "projected") {
      return invalid(key, "'" + value + "' is not a support mode (auto, none, projected)");
    }
    settings.support.mode = value;
    return {};
  }
  if (key == "multidir.scheme") {
    if (value != "beam" && value != "greedy" && value != "constrained") {
      return invalid(key, "'" + value + "' is not a search scheme (beam, greedy, constrained)");
    }
    settings.multidir.scheme = value;
    return {};
  }
  if (key == "multidir.dof") {
    if (value != "auto" && value != "4dof" && value != "5dof") {
      return invalid(key, "'" + value + "' is not a mode (auto, 4dof, 5dof)");
    }
    settings.multidir.dof = value;
    return {};
  }
  if (key == "geodesic.remesh") {
    bool b = false;
    if (!parseBool(value, b)) return invalid(key, "expected true or false");
    settings.geodesic.remesh = b;
    return {};
  }
  if (key == "isoplanar.benchmark") {
    bool b = false;
    if (!parseBool(value, b)) return invalid(key, "expected true or false");
    settings.isoplanar.benchmark = b;
    return {};
  }
  if (key == "voxel.strategy") {
    if (value != "gcfa" && value != "sp-gcfa" && value != "pg-gcfa" && value != "pg-sp-gcfa") {
      return invalid(key, "'" + value + "' is not a strategy (gcfa, sp-gcfa, pg-gcfa, pg-sp-gcfa)");
    }
    settings.voxel.strategy = value;
    return {};
  }
  if (key == "voxel.shadow") {
    if (value != "incremental" && value != "recursive") {
      return invalid(key, "'" + value + "' is not a shadow scheme (incremental, recursive)");
    }
    settings.voxel.shadow = value;
    return {};
  }
  if (key == "voxel.layer_field") {
    if (value != "steps" && value != "generations" && value != "distance") {
      return invalid(key, "'" + value + "' is not a layer field (steps, generations, distance)");
    }
    settings.voxel.layerField = value;
    return {};
  }
  if (key == "voxel.supports") {
    bool b = false;
    if (!parseBool(value, b)) return invalid(key, "expected true or false");
    settings.voxel.supports = b;
    return {};
  }
  if (key == "machine") {
    const std::vector<std::string> names = builtinMachineNames();
    bool known = false;
    std::string list;
    for (const std::string& n : names) {
      known = known || n == value;
      list += (list.empty() ? "" : ", ") + n;
    }
    if (!known && value != "robot6") {
      return invalid(key, "'" + value + "' is not a built-in machine (" + list +
                              "; a profile file goes in machine_json)");
    }
    settings.machine = value;
    return {};
  }
  if (key == "machine_json") {
    if (!value.empty()) {
      MachineParseResult m = machineFromJson(value);
      if (!m.ok()) return invalid(key, m.message);
    }
    settings.machineJson = value;
    return {};
  }
  if (key == "gcode_flavor") {
    if (value != "marlin" && value != "reprap" && value != "klipper") {
      return invalid(key, "'" + value + "' is not a G-code flavour (marlin, reprap, klipper)");
    }
    settings.gcodeFlavor = value;
    return {};
  }
  if (key == "robot_format") {
    if (value != "csv" && value != "urscript") {
      return invalid(key, "'" + value + "' is not a robot program format (csv, urscript)");
    }
    settings.robotFormat = value;
    return {};
  }
  if (key == "motion.smooth_orientations") {
    bool b = false;
    if (!parseBool(value, b)) return invalid(key, "expected true or false");
    settings.smoothOrientations = b;
    return {};
  }
  if (key == "direction") {
    Eigen::Vector3d d;
    if (!parseVector(value, d)) return invalid(key, "expected three numbers 'x,y,z'");
    if (d.norm() < 1e-9) return invalid(key, "the direction must not be zero");
    settings.direction = d.normalized();
    return {};
  }
  if (key == "bed_size") {
    Eigen::Vector3d b;
    if (!parseVector(value, b)) return invalid(key, "expected three numbers 'x,y,z' in mm");
    if (b.minCoeff() <= 0 || b.maxCoeff() > 10000) return invalid(key, "each size must be in (0, 10000] mm");
    settings.bedSize = b;
    return {};
  }
  if (key == "infill_pattern") {
    if (value == "lines") settings.infillPattern = InfillPattern::Lines;
    else if (value == "grid") settings.infillPattern = InfillPattern::Grid;
    else return invalid(key, "'" + value + "' is not a pattern (lines, grid)");
    return {};
  }
  if (key == "up") {
    static const std::map<std::string, UpAxis> axes = {
        {"z", UpAxis::PosZ}, {"+z", UpAxis::PosZ}, {"-z", UpAxis::NegZ}, {"y", UpAxis::PosY},
        {"+y", UpAxis::PosY}, {"-y", UpAxis::NegY}, {"x", UpAxis::PosX}, {"+x", UpAxis::PosX},
        {"-x", UpAxis::NegX}};
    std::string v = value;
    for (char& c : v) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    auto it = axes.find(v);
    if (it == axes.end()) return invalid(key, "'" + value + "' is not an axis (z, -z, y, -y, x, -x)");
    settings.placement.up = it->second;
    return {};
  }
  if (key == "center") {
    bool b = false;
    if (!parseBool(value, b)) return invalid(key, "expected true or false");
    settings.placement.center = b;
    return {};
  }
  return {Status::InvalidOption, "unknown setting '" + rawKey + "'"};
}

Outcome validateSettings(const Settings& s) {
  if (s.layerHeight > s.nozzleDiameter) {
    return {Status::InvalidOption, "setting 'layer_height': " + formatNumber(s.layerHeight) +
                                       " mm is thicker than the nozzle (" +
                                       formatNumber(s.nozzleDiameter) + " mm)"};
  }
  if (s.effectiveFirstLayerHeight() > s.nozzleDiameter) {
    return {Status::InvalidOption, "setting 'first_layer_height' is thicker than the nozzle"};
  }
  const double w = s.effectiveLineWidth();
  if (w < 0.5 * s.nozzleDiameter || w > 3 * s.nozzleDiameter) {
    return {Status::InvalidOption, "setting 'line_width': " + formatNumber(w) +
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
  if (s.fill == "spiral" && s.method != "voxel") {
    return {Status::InvalidOption, "setting 'fill': spiral fills curved layers of method voxel only"};
  }
  return {};
}

std::vector<std::pair<std::string, std::string>> listSettings(const Settings& s) {
  // Resolved values (line width, first layer) so a header states what was printed.
  Settings copy = s;
  copy.lineWidth = s.effectiveLineWidth();
  copy.firstLayerHeight = s.effectiveFirstLayerHeight();
  std::vector<std::pair<std::string, std::string>> out;
  out.emplace_back("method", s.method);
  out.emplace_back("machine", s.machine);
  out.emplace_back("direction", formatVector(s.direction));
  for (const auto& [key, spec] : numberSpecs()) out.emplace_back(key, formatNumber(spec.field(copy)));
  for (const auto& [key, spec] : intSpecs()) out.emplace_back(key, std::to_string(spec.field(copy)));
  out.emplace_back("infill_pattern", s.infillPattern == InfillPattern::Lines ? "lines" : "grid");
  out.emplace_back("up", upAxisName(s.placement.up));
  out.emplace_back("center", s.placement.center ? "true" : "false");
  out.emplace_back("bed_size", formatVector(s.bedSize));
  out.emplace_back("gcode_flavor", s.gcodeFlavor);
  out.emplace_back("robot_format", s.robotFormat);
  out.emplace_back("motion.smooth_orientations", s.smoothOrientations ? "true" : "false");
  out.emplace_back("fill", s.fill);
  out.emplace_back("isoplanar.benchmark", s.isoplanar.benchmark ? "true" : "false");
  out.emplace_back("support", s.support.mode);
  if (s.method == "voxel") {
    out.emplace_back("voxel.strategy", s.voxel.strategy);
    out.emplace_back("voxel.shadow", s.voxel.shadow);
    out.emplace_back("voxel.supports", s.voxel.supports ? "true" : "false");
    out.emplace_back("voxel.layer_field", s.voxel.layerField);
  }
  if (s.method == "multidir") {
    out.emplace_back("multidir.scheme", s.multidir.scheme);
    out.emplace_back("multidir.dof", s.multidir.dof);
  }
  if (s.method == "geodesic") {
    out.emplace_back("geodesic.sequence", s.geodesic.sequence);
    out.emplace_back("geodesic.remesh", s.geodesic.remesh ? "true" : "false");
  }
  // machine_json is not listed: the program header and the report carry the resolved profile.
  return out;
}

}  // namespace omnislice
