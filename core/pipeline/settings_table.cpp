// SPDX-License-Identifier: MIT
// The settings table: every setting once, with its type, range, unit, help and choices. Its order
// is the order of listSettings() (program headers and reports keep it, so it stays): the general
// choices, then the numbers and the whole numbers each by key, then the other choices, then the
// method-specific choices.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "machine/machine.h"
#include "machine/machine_json.h"
#include "pipeline/settings.h"
#include "program/thumbnail.h"

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

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// ---- builders: one per type --------------------------------------------------------------------

// A field of the settings. Formatting reads through it from a const Settings (the accessors
// only return a reference; nothing is written there).
template <typename T>
using Field = T& (*)(Settings&);

template <typename T>
const T& read(Field<T> field, const Settings& settings) {
  return field(const_cast<Settings&>(settings));
}

SettingSpec number(const char* key, Field<double> field, double min, double max, const char* unit,
                   const char* help) {
  SettingSpec s;
  s.key = key;
  s.type = SettingType::Number;
  s.min = min;
  s.max = max;
  s.unit = unit;
  s.help = help;
  const std::string k = key;
  s.parse = [field, min, max, k, unit = std::string(unit)](Settings& st, const std::string& text) -> Outcome {
    double v = 0;
    if (!parseNumber(text, v)) return invalid(k, "'" + text + "' is not a finite number");
    if (v < min || v > max) {
      return invalid(k, formatSettingNumber(v) + " is outside [" + formatSettingNumber(min) + ", " +
                            formatSettingNumber(max) + "]" + (unit.empty() ? "" : " " + unit));
    }
    field(st) = v;
    return {};
  };
  s.format = [field](const Settings& st) { return formatSettingNumber(read(field, st)); };
  return s;
}

SettingSpec integer(const char* key, Field<int> field, int min, int max, const char* unit, const char* help) {
  SettingSpec s;
  s.key = key;
  s.type = SettingType::Integer;
  s.min = min;
  s.max = max;
  s.unit = unit;
  s.help = help;
  const std::string k = key;
  s.parse = [field, min, max, k](Settings& st, const std::string& text) -> Outcome {
    double v = 0;
    if (!parseNumber(text, v) || v != std::floor(v)) return invalid(k, "'" + text + "' is not a whole number");
    if (v < min || v > max) {
      return invalid(k, formatSettingNumber(v) + " is outside [" + std::to_string(min) + ", " +
                            std::to_string(max) + "]");
    }
    field(st) = static_cast<int>(v);
    return {};
  };
  s.format = [field](const Settings& st) { return std::to_string(read(field, st)); };
  return s;
}

SettingSpec boolean(const char* key, Field<bool> field, const char* help) {
  SettingSpec s;
  s.key = key;
  s.type = SettingType::Boolean;
  s.help = help;
  s.choices = {"true", "false"};
  const std::string k = key;
  s.parse = [field, k](Settings& st, const std::string& text) -> Outcome {
    bool b = false;
    if (!parseBool(text, b)) return invalid(k, "expected true or false");
    field(st) = b;
    return {};
  };
  s.format = [field](const Settings& st) { return std::string(read(field, st) ? "true" : "false"); };
  return s;
}

// A choice among named values of an enum. `noun` names what the values are in messages ("'x' is
// not a fill (auto, isoplanar, spiral)"); aliases are other accepted spellings; anyCase accepts
// any letter case.
template <typename E>
SettingSpec choice(const char* key, Field<E> field, std::vector<std::pair<std::string, E>> values, const char* noun,
                   const char* help, std::vector<std::pair<std::string, E>> aliases = {}, bool anyCase = false) {
  SettingSpec s;
  s.key = key;
  s.type = SettingType::Choice;
  s.help = help;
  for (const auto& v : values) s.choices.push_back(v.first);
  const std::string k = key, what = noun;
  const std::vector<std::string> names = s.choices;
  std::vector<std::pair<std::string, E>> accepted = values;
  accepted.insert(accepted.end(), aliases.begin(), aliases.end());
  s.parse = [field, accepted, k, what, names, anyCase](Settings& st, const std::string& text) -> Outcome {
    const std::string t = anyCase ? lowercase(text) : text;
    for (const auto& [name, value] : accepted) {
      if (name == t) {
        field(st) = value;
        return {};
      }
    }
    return invalid(k, "'" + text + "' is not " + what + " (" + joined(names) + ")");
  };
  s.format = [field, values](const Settings& st) {
    const E v = read(field, st);
    for (const auto& [name, value] : values) {
      if (value == v) return name;
    }
    return values.front().first;
  };
  return s;
}

// A vector "x,y,z" with a check of the parsed value (an empty message accepts it).
SettingSpec vector3(const char* key, Field<Eigen::Vector3d> field, const char* unit, const char* help,
                    const char* expected, std::string (*check)(Eigen::Vector3d&)) {
  SettingSpec s;
  s.key = key;
  s.type = SettingType::Vector;
  s.unit = unit;
  s.help = help;
  const std::string k = key, exp = expected;
  s.parse = [field, k, exp, check](Settings& st, const std::string& text) -> Outcome {
    Eigen::Vector3d v;
    if (!parseVector(text, v)) return invalid(k, exp);
    if (const std::string why = check(v); !why.empty()) return invalid(k, why);
    field(st) = v;
    return {};
  };
  s.format = [field](const Settings& st) { return formatSettingVector(read(field, st)); };
  return s;
}

SettingSpec unlisted(SettingSpec s) {
  s.listed = false;
  return s;
}

SettingSpec onlyWith(Method method, SettingSpec s) {
  s.onlyFor = method;
  return s;
}

std::vector<std::pair<std::string, Method>> methodChoices() {
  std::vector<std::pair<std::string, Method>> out;
  for (Method m : {Method::Planar, Method::Voxel, Method::Surface, Method::Geodesic, Method::Multidir, Method::Auto}) {
    out.emplace_back(methodName(m), m);
  }
  return out;
}

SettingSpec machineSpec() {
  SettingSpec s;
  s.key = "machine";
  s.type = SettingType::Choice;
  s.help = "built-in machine profile (machine_json overrides it)";
  s.choices = builtinMachineNames();
  s.parse = [](Settings& st, const std::string& value) -> Outcome {
    const std::vector<std::string> names = builtinMachineNames();
    bool known = value == "robot6";  // the arm's short name
    for (const std::string& n : names) known = known || n == value;
    if (!known) {
      return invalid("machine", "'" + value + "' is not a built-in machine (" + joined(names) +
                                    "; a profile file goes in machine_json)");
    }
    st.machine = value;
    return {};
  };
  s.format = [](const Settings& st) { return st.machine; };
  return s;
}

SettingSpec machineJsonSpec() {
  SettingSpec s;
  s.key = "machine_json";
  s.type = SettingType::Text;
  s.help = "a user's machine profile (docs/MACHINES.md); overrides machine when not empty";
  s.listed = false;  // the program header and the report carry the resolved profile
  s.parse = [](Settings& st, const std::string& value) -> Outcome {
    if (!value.empty()) {
      MachineParseResult m = machineFromJson(value);
      if (!m.ok()) return invalid("machine_json", m.message);
    }
    st.machineJson = value;
    return {};
  };
  s.format = [](const Settings& st) { return st.machineJson; };
  return s;
}

// "B=U,C=V" (also spaces or semicolons between pairs; letters in either case): the firmware's
// letter for an axis. Empty = the profile's. Whether the axes are the machine's is checked when
// the machine is resolved (checkAxisLetters).
SettingSpec axisLettersSpec() {
  SettingSpec s;
  s.key = "axis_letters";
  s.type = SettingType::Text;
  s.help = "G-code machines: the letter the firmware uses for an axis, e.g. B=U,C=V (RepRapFirmware rotary axes); "
           "empty = the profile's axis_letters";
  s.listed = false;  // the program header's machine JSON carries them
  s.parse = [](Settings& st, const std::string& value) -> Outcome {
    std::string text = value;
    for (char& c : text) {
      if (c == ',' || c == ';') c = ' ';
      c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    std::istringstream in(text);
    std::map<std::string, std::string> letters;
    for (std::string pair; in >> pair;) {
      const size_t eq = pair.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == pair.size()) {
        return invalid("axis_letters", "expected AXIS=LETTER pairs such as B=U,C=V, not '" + pair.substr(0, 20) + "'");
      }
      const std::string axis = pair.substr(0, eq);
      if (letters.count(axis)) return invalid("axis_letters", "axis " + axis.substr(0, 20) + " named twice");
      letters[axis] = pair.substr(eq + 1);
    }
    st.axisLetters = std::move(letters);
    return {};
  };
  s.format = [](const Settings& st) {
    std::string out;
    for (const auto& [axis, letter] : st.axisLetters) out += (out.empty() ? "" : ",") + axis + "=" + letter;
    return out;
  };
  return s;
}

// "16x16,220x124": PNG thumbnails in the G-code for printer hosts (program/thumbnail.h).
SettingSpec thumbnailsSpec() {
  SettingSpec s;
  s.key = "thumbnails";
  s.type = SettingType::Text;
  s.help = "G-code machines: PNG thumbnails of the part for printer hosts (OctoPrint, Moonraker, Prusa), "
           "WIDTHxHEIGHT each, e.g. 16x16,220x124 (PrusaSlicer's comment block); empty = none";
  s.listed = false;  // the program carries the blocks themselves
  s.parse = [](Settings& st, const std::string& value) -> Outcome {
    ThumbnailSizes sizes = parseThumbnailSizes(value);
    if (!sizes.ok()) return invalid("thumbnails", sizes.message);
    st.thumbnails = std::move(sizes.sizes);
    return {};
  };
  s.format = [](const Settings& st) {
    std::string out;
    for (const auto& [w, h] : st.thumbnails) out += (out.empty() ? "" : ",") + std::to_string(w) + "x" + std::to_string(h);
    return out;
  };
  return s;
}

// The slicing direction, normalised unless already of unit length within 1e-9: a normalised
// direction listed by listSettings() (10 significant digits) is unit within about 1e-10, so setting
// the listed value again keeps it as read and lists the same (renormalising it could move its 10th
// digit: found by the settings fuzz target). Its user, pipeline.cpp, normalises it again.
std::string nonZero(Eigen::Vector3d& d) {
  const double n = d.norm();
  if (!(n >= 1e-9)) return "the direction must not be zero";
  if (std::abs(n - 1) > 1e-9) d /= n;
  return "";
}

std::string bedSizeRange(Eigen::Vector3d& b) {
  if (b.minCoeff() <= 0 || b.maxCoeff() > 10000) return "each size must be in (0, 10000] mm";
  return "";
}

std::vector<SettingSpec> makeTable() {
  using S = Settings;
  std::vector<SettingSpec> t = {
      // ---- general choices -----------------------------------------------------------------
      choice<Method>("method", [](S& s) -> Method& { return s.method; }, methodChoices(), "a method",
                     "slicing method: planar layers, or a multi-axis method of the papers; auto runs every method "
                     "the machine takes, verifies each program and delivers the best (sound first, then "
                     "supported, less support, less time)"),
      machineSpec(),
      vector3("direction", [](S& s) -> Eigen::Vector3d& { return s.direction; }, "",
              "planar: slicing direction d in the part frame (normalised); on cartesian3 the part is "
              "turned so d points up",
              "expected three numbers 'x,y,z'", nonZero),
      // ---- numbers, by key -------------------------------------------------------------------
      number("acceleration", [](S& s) -> double& { return s.acceleration; }, 0, 100000, "mm/s^2",
             "time estimate only (0 = ignore)"),
      number("bed_temperature", [](S& s) -> double& { return s.bedTemperature; }, 0, 200, "deg C", "0 = no heating"),
      number("bridge_flow", [](S& s) -> double& { return s.bridgeFlowPercent; }, 1, 200, "%",
             "planar bridges: filament of a bead's"),
      number("bridge_speed", [](S& s) -> double& { return s.bridgeSpeed; }, 1, 1000, "mm/s", "planar bridges"),
      number("bridge_fan_speed", [](S& s) -> double& { return s.bridgeFanPercent; }, 0, 100, "%",
             "part cooling fan while printing bridges (G-code machines)"),
      number("fan_speed", [](S& s) -> double& { return s.fanPercent; }, 0, 100, "%",
             "part cooling fan after the first fan_off_layers (G-code machines: M106/M107)"),
      number("filament_diameter", [](S& s) -> double& { return s.filamentDiameter; }, 0.5, 5, "mm", ""),
      number("first_layer_height", [](S& s) -> double& { return s.firstLayerHeight; }, 0, 5, "mm",
             "0 = layer_height"),
      number("first_layer_speed", [](S& s) -> double& { return s.firstLayerSpeed; }, 1, 1000, "mm/s",
             "every feature of the first layer"),
      number("fit_mm", [](S& s) -> double& { return s.placement.fitMm; }, 0, 1e5, "mm",
             "scale so the largest side is this long (0 = off; overrides scale)"),
      number("geodesic.base_band_mm", [](S& s) -> double& { return s.geodesic.baseBandMm; }, 0, 20, "mm",
             "heat source: the part within this of the platform (0 = a quarter interval)"),
      number("geodesic.interval_mm", [](S& s) -> double& { return s.geodesic.intervalMm; }, 0, 20, "mm",
             "geodesic distance between layers (0 = layer_height)"),
      number("geodesic.max_thickness_ratio", [](S& s) -> double& { return s.geodesic.maxThicknessRatio; }, 0, 3,
             "intervals", "largest layer thickness at the surface (0 = uniform iso-values i d, the paper)"),
      number("geodesic.nozzle_angle_deg", [](S& s) -> double& { return s.geodesic.nozzleAngleDeg; }, 0, 89, "deg",
             "nozzle cone of the collision model (0 = the machine's)"),
      number("geodesic.target_tets", [](S& s) -> double& { return s.geodesic.targetTets; }, 100, 3e6, "tets",
             "tets the mesher aims at when geodesic.tet_size_mm is 0"),
      number("geodesic.tet_size_mm", [](S& s) -> double& { return s.geodesic.tetSizeMm; }, 0, 100, "mm",
             "tet lattice spacing (0 = from geodesic.target_tets)"),
      number("infill", [](S& s) -> double& { return s.infillPercent; }, 0, 100, "%",
             "sparse infill density (100 = solid); voxel and geodesic: the curved layers' interior "
             "spirals, spaced line width x 100 / infill, inside a solid shell"),
      number("infill_angle_deg", [](S& s) -> double& { return s.infillAngleDegrees; }, -360, 360, "deg",
             "angle of the infill lines in the layer plane"),
      number("infill_overlap_pct", [](S& s) -> double& { return s.infillOverlapPercent; }, 0, 100,
             "% of line width", "infill overlap into the innermost wall"),
      number("infill_speed", [](S& s) -> double& { return s.infillSpeed; }, 1, 1000, "mm/s", ""),
      number("isoplanar.chord_error_mm", [](S& s) -> double& { return s.isoplanar.chordErrorMm; }, 0, 10, "mm",
             "chord error of Eq. 12 (0 = min(0.5, layer height / 8))"),
      number("isoplanar.directions", [](S& s) -> double& { return s.isoplanar.directions; }, 1, 3600, "directions",
             "drive directions sampled over [0, 180) for theta*"),
      number("isoplanar.gamma_samples", [](S& s) -> double& { return s.isoplanar.gammaSamples; }, 4, 720, "samples",
             "robot6: rotations about the nozzle sampled (Eq. 6)"),
      number("isoplanar.max_feed_mm_s", [](S& s) -> double& { return s.isoplanar.maxFeedMmS; }, 0, 2000, "mm/s",
             "cap on the kinematic feed f* (0 = print_speed)"),
      number("isoplanar.stencil_mm", [](S& s) -> double& { return s.isoplanar.stencilMm; }, 0.05, 20, "mm",
             "l_c of Eq. 7"),
      number("isoplanar.theta_deg", [](S& s) -> double& { return s.isoplanar.thetaDegrees; }, -1, 180, "deg",
             "drive-plane angle in [0, 180) (-1 = search theta*)"),
      number("junction_deviation", [](S& s) -> double& { return s.junctionDeviation; }, 0, 10, "mm",
             "time estimate only: the firmware's junction deviation (how fast corners are taken; Marlin's "
             "default 0.013; 0 = every move from and to rest)"),
      number("layer_height", [](S& s) -> double& { return s.layerHeight; }, 0.01, 5, "mm", "at most the nozzle"),
      number("line_width", [](S& s) -> double& { return s.lineWidth; }, 0, 10, "mm", "0 = 1.125 x nozzle"),
      number("motion.chord_tolerance", [](S& s) -> double& { return s.chordTolerance; }, 0.0001, 1, "mm",
             "machine interpolation vs the part-frame path"),
      number("motion.filter_deg", [](S& s) -> double& { return s.orientationFilterDegrees; }, 0.1, 180, "deg",
             "orientation filter where neighbouring axes differ by more"),
      number("motion.axis_freedom_deg", [](S& s) -> double& { return s.axisFreedomDegrees; }, -1, 45, "deg",
             "curved layers: how far the nozzle axis may lean from the layer's ideal axis to keep the "
             "rotary axes still (0 = the ideal axis, -1 = the method's: geodesic 25, voxel 15)"),
      number("multidir.alpha_max_deg", [](S& s) -> double& { return s.multidir.alphaMaxDeg; }, 1, 89, "deg",
             "maximal self-supporting angle"),
      number("multidir.interface_overlap", [](S& s) -> double& { return s.multidir.interfaceOverlap; }, 0, 1, "",
             "fraction of the overlap an earlier part may have across a later part's plane"),
      number("multidir.max_tilt_deg", [](S& s) -> double& { return s.multidir.maxTiltDeg; }, 0, 180, "deg",
             "5dof: largest tilt of a part's direction (0 = the machine's)"),
      number("multidir.offset_step_mm", [](S& s) -> double& { return s.multidir.offsetStepMm; }, 0.05, 100, "mm",
             "candidate plane offsets along each normal"),
      number("multidir.platform_margin_mm", [](S& s) -> double& { return s.multidir.platformMarginMm; }, 0, 1000,
             "mm", "Criterion III: the platform is the footprint grown by this"),
      number("multidir.step_angle_deg", [](S& s) -> double& { return s.multidir.stepAngleDeg; }, 0, 90, "deg",
             "4dof: stepper angle (0 = the machine's)"),
      number("multidir.w", [](S& s) -> double& { return s.multidir.w; }, 1, 1000, "",
             "parts smaller than V / w are refused (Criterion IV)"),
      number("nozzle_diameter", [](S& s) -> double& { return s.nozzleDiameter; }, 0.05, 5, "mm", ""),
      number("nozzle_temperature", [](S& s) -> double& { return s.nozzleTemperature; }, 0, 500, "deg C",
             "0 = no heating"),
      number("outer_wall_speed", [](S& s) -> double& { return s.outerWallSpeed; }, 1, 1000, "mm/s", ""),
      number("print_speed", [](S& s) -> double& { return s.printSpeed; }, 1, 1000, "mm/s",
             "inner walls, skin, curved layers"),
      number("retract_inside_max_travel", [](S& s) -> double& { return s.retractInsideMaxTravel; }, 0, 1000, "mm",
             "planar travels that stay inside the part (travel_inside) retract only when longer"),
      number("retract_length", [](S& s) -> double& { return s.retractLength; }, 0, 20, "mm", "of filament (0 = off)"),
      number("retract_min_travel", [](S& s) -> double& { return s.retractMinTravel; }, 0, 1000, "mm",
             "shorter travels do not retract"),
      number("retract_speed", [](S& s) -> double& { return s.retractSpeed; }, 1, 200, "mm/s", "of filament"),
      number("rotate_x_deg", [](S& s) -> double& { return s.placement.rotateXDegrees; }, -360, 360, "deg",
             "turn about the part's X after the up axis"),
      number("rotate_y_deg", [](S& s) -> double& { return s.placement.rotateYDegrees; }, -360, 360, "deg",
             "then about Y"),
      number("rotate_z_deg", [](S& s) -> double& { return s.placement.rotateZDegrees; }, -360, 360, "deg",
             "then about Z"),
      number("scale", [](S& s) -> double& { return s.placement.scale; }, 1e-6, 1e6, "factor", "uniform scale"),
      number("support.angle_deg", [](S& s) -> double& { return s.support.angleDeg; }, 0, 89, "deg",
             "overhangs steeper than this get support (0 = the method's)"),
      number("support.auto_share_pct", [](S& s) -> double& { return s.support.autoSharePercent; }, 0, 100, "%",
             "support = auto, planar: supports when more of the part's surface than this overhangs"),
      number("support.gap_mm", [](S& s) -> double& { return s.support.gapMm; }, 0, 5, "mm",
             "horizontal gap between support and the part"),
      number("support.lambda", [](S& s) -> double& { return s.support.lambda; }, 0, 1, "",
             "Eq. 13: strut diameter growth with the torque above"),
      number("support.merge_angle_deg", [](S& s) -> double& { return s.support.mergeAngleDeg; }, 0, 60, "deg",
             "tree branches at most this far from the direction (0 = straight columns)"),
      number("support.min_diameter_mm", [](S& s) -> double& { return s.support.minDiameterMm; }, 0, 20, "mm",
             "strut diameter floor (0 = 2 x line width)"),
      number("support.sampling_mm", [](S& s) -> double& { return s.support.samplingMm; }, 0, 50, "mm",
             "overhang sampling interval R (0 = 2.5 x nozzle + 1)"),
      number("surface.base_mm", [](S& s) -> double& { return s.surface.baseMm; }, 0.1, 500, "mm",
             "thinnest support base under the surface layer"),
      number("travel_speed", [](S& s) -> double& { return s.travelSpeed; }, 1, 2000, "mm/s", ""),
      number("voxel.epsilon", [](S& s) -> double& { return s.voxel.epsilon; }, -1, 2, "voxel widths",
             "hull tolerance of Definitions 2-3 (-1 = the field's default)"),
      number("voxel.iso_step", [](S& s) -> double& { return s.voxel.isoStep; }, 0, 100, "field units",
             "curved-layer iso step (0 = from voxel.layer_mm)"),
      number("voxel.layer_mm", [](S& s) -> double& { return s.voxel.layerMm; }, 0, 5, "mm",
             "target curved-layer thickness (0 = the voxel width)"),
      number("voxel.max_thickness_ratio", [](S& s) -> double& { return s.voxel.maxThicknessRatio; }, 0, 10,
             "x layer", "partial layers where a layer lies further than this from the one below (0 = off)"),
      number("voxel.max_tilt_deg", [](S& s) -> double& { return s.voxel.maxTiltDegrees; }, 0, 180, "deg",
             "nozzle axes lean at most this far from +Z (0 = the machine's)"),
      number("voxel.max_voxels", [](S& s) -> double& { return s.voxel.maxVoxels; }, 1000, 1e9, "voxels",
             "refuse grids with more solid voxels"),
      number("voxel.peel_step", [](S& s) -> double& { return s.voxel.peelStep; }, 0.01, 1000, "peeling sheets",
             "delta f of Algorithm 1"),
      number("voxel.platform_radius_mm", [](S& s) -> double& { return s.voxel.platformRadiusMm; }, 0, 5000, "mm",
             "platform disc radius (0 = the part's footprint)"),
      number("voxel.smooth", [](S& s) -> double& { return s.voxel.smoothIterations; }, 0, 200, "passes",
             "Jacobi smoothing of the layer field (0 = as grown)"),
      number("voxel.width_mm", [](S& s) -> double& { return s.voxel.widthMm; }, 0, 50, "mm",
             "voxel width (0 = 0.8 x nozzle)"),
      // ---- whole numbers, by key -------------------------------------------------------------
      integer("bottom_layers", [](S& s) -> int& { return s.bottomLayers; }, 0, 200, "layers",
              "solid layers over a bottom surface"),
      integer("fan_off_layers", [](S& s) -> int& { return s.fanOffLayers; }, 0, 1000, "layers",
              "the first layers printed (counted over the parts) with the part cooling fan off"),
      integer("motion.free_rotation_samples", [](S& s) -> int& { return s.freeRotationSamples; }, 1, 360, "samples",
              "robot6: rotations about the nozzle axis tried"),
      integer("multidir.axis_search", [](S& s) -> int& { return s.multidir.axisSearch; }, 0, 3600, "axes",
              "4dof: try this many horizontal rotation axes (0 = the machine's)"),
      integer("multidir.beam_width", [](S& s) -> int& { return s.multidir.beamWidth; }, 1, 100, "beams",
              "beams per search level"),
      integer("multidir.perturbations", [](S& s) -> int& { return s.multidir.perturbations; }, 0, 10000, "moves",
              "iterated local search moves on the refined planes (0 = off)"),
      integer("multidir.restarts", [](S& s) -> int& { return s.multidir.restarts; }, 1, 64, "searches",
              "5dof beam: searches on spheres of normals turned about Z"),
      integer("multidir.samples", [](S& s) -> int& { return s.multidir.samples; }, 4, 20000, "normals",
              "candidate normals on the sphere (or circle, 4dof)"),
      integer("support.roof_layers", [](S& s) -> int& { return s.support.roofLayers; }, 0, 100, "layers",
              "solid support layers right under an overhang"),
      integer("top_layers", [](S& s) -> int& { return s.topLayers; }, 0, 200, "layers",
              "solid layers under a top surface"),
      integer("walls", [](S& s) -> int& { return s.walls; }, 0, 50, "walls", "perimeters per island"),
      // ---- other choices ---------------------------------------------------------------------
      choice<InfillPattern>("infill_pattern", [](S& s) -> InfillPattern& { return s.infillPattern; },
                            {{"lines", InfillPattern::Lines}, {"grid", InfillPattern::Grid}}, "a pattern",
                            "sparse infill: lines (turning 90 degrees by layer) or grid"),
      choice<SeamPlacement>("seam", [](S& s) -> SeamPlacement& { return s.seam; },
                            {{"aligned", SeamPlacement::Aligned}, {"nearest", SeamPlacement::Nearest},
                             {"sharpest", SeamPlacement::Sharpest}, {"random", SeamPlacement::Random}},
                            "a seam placement",
                            "where planar wall loops start: aligned (in corners, lined up with the layer "
                            "below; else at the rear), nearest (to the nozzle: the least travel), sharpest "
                            "(corner, concave first) or random"),
      choice<UpAxis>("up", [](S& s) -> UpAxis& { return s.placement.up; },
                     {{"z", UpAxis::PosZ}, {"-z", UpAxis::NegZ}, {"y", UpAxis::PosY}, {"-y", UpAxis::NegY},
                      {"x", UpAxis::PosX}, {"-x", UpAxis::NegX}},
                     "an axis", "which axis of the file points up on the platform",
                     {{"+z", UpAxis::PosZ}, {"+y", UpAxis::PosY}, {"+x", UpAxis::PosX}}, true),
      boolean("bridges", [](S& s) -> bool& { return s.bridges; },
              "planar skin over air anchored on both sides is printed as bridge lines across the span"),
      boolean("gap_fill", [](S& s) -> bool& { return s.gapFill; },
              "planar: strips between walls too narrow for another wall (0.3 to 1 line wide) are filled "
              "with lines across them"),
      boolean("travel_inside", [](S& s) -> bool& { return s.travelInside; },
              "planar travels within a section keep inside it (round holes and notches) instead of "
              "crossing walls"),
      boolean("center", [](S& s) -> bool& { return s.placement.center; },
              "centre the part on the platform in XY (else keep XY as read)"),
      vector3("bed_size", [](S& s) -> Eigen::Vector3d& { return s.bedSize; }, "mm",
              "built-in machines: the travel of X, Y, Z", "expected three numbers 'x,y,z' in mm", bedSizeRange),
      choice<GcodeDialect>("gcode_flavor", [](S& s) -> GcodeDialect& { return s.gcodeFlavor; },
                           {{gcodeDialectName(GcodeDialect::Marlin), GcodeDialect::Marlin},
                            {gcodeDialectName(GcodeDialect::RepRap), GcodeDialect::RepRap},
                            {gcodeDialectName(GcodeDialect::Klipper), GcodeDialect::Klipper}},
                           "a G-code flavour", "firmware dialect of G-code programs"),
      choice<RobotFormat>("robot_format", [](S& s) -> RobotFormat& { return s.robotFormat; },
                          {{robotFormatName(RobotFormat::Csv), RobotFormat::Csv},
                           {robotFormatName(RobotFormat::UrScript), RobotFormat::UrScript},
                           {robotFormatName(RobotFormat::Rapid), RobotFormat::Rapid},
                           {robotFormatName(RobotFormat::Krl), RobotFormat::Krl}},
                          "a robot program format", "robot6: joint CSV, URScript, ABB RAPID or KUKA KRL"),
      boolean("motion.smooth_orientations", [](S& s) -> bool& { return s.smoothOrientations; },
              "paper 001 Section 5.2 orientation filter"),
      choice<FillMode>("fill", [](S& s) -> FillMode& { return s.fill; },
                       {{"auto", FillMode::Auto}, {"isoplanar", FillMode::Isoplanar}, {"spiral", FillMode::Spiral}},
                       "a fill",
                       "auto (planar: walls and infill; curved layers: Fermat spirals; surface: iso-planar), "
                       "isoplanar (paper 003) or spiral (voxel)"),
      boolean("isoplanar.benchmark", [](S& s) -> bool& { return s.isoplanar.benchmark; },
              "surface: plan every other sampled direction too and report their mean time"),
      choice<SupportMode>("support", [](S& s) -> SupportMode& { return s.support.mode; },
                          {{"auto", SupportMode::Auto}, {"none", SupportMode::None},
                           {"projected", SupportMode::Projected}},
                          "a support mode", "auto (multidir: projected; planar: projected when more of the surface than support.auto_share_pct overhangs, else none; voxel and geodesic: fins when beads over air are the one failure left and they make the program sound), none or projected"),
      // ---- method-specific choices (listed only with their method) ------------------------------
      onlyWith(Method::Voxel,
               choice<GrowthStrategy>("voxel.strategy", [](S& s) -> GrowthStrategy& { return s.voxel.strategy; },
                                      {{growthStrategyName(GrowthStrategy::Gcfa), GrowthStrategy::Gcfa},
                                       {growthStrategyName(GrowthStrategy::SpGcfa), GrowthStrategy::SpGcfa},
                                       {growthStrategyName(GrowthStrategy::PgGcfa), GrowthStrategy::PgGcfa},
                                       {growthStrategyName(GrowthStrategy::PgSpGcfa), GrowthStrategy::PgSpGcfa}},
                                      "a strategy", "growth: convex-front advancing variants (Algorithm 1)")),
      onlyWith(Method::Voxel,
               choice<ShadowScheme>("voxel.shadow", [](S& s) -> ShadowScheme& { return s.voxel.shadow; },
                                    {{shadowSchemeName(ShadowScheme::Incremental), ShadowScheme::Incremental},
                                     {shadowSchemeName(ShadowScheme::RecursivePca), ShadowScheme::RecursivePca}},
                                    "a shadow scheme", "shadow prevention")),
      onlyWith(Method::Voxel, boolean("voxel.supports", [](S& s) -> bool& { return s.voxel.supports; },
                                      "add supports under missed voxels and grow again")),
      onlyWith(Method::Voxel,
               choice<LayerField>("voxel.layer_field", [](S& s) -> LayerField& { return s.voxel.layerField; },
                                  {{layerFieldName(LayerField::Steps), LayerField::Steps},
                                   {layerFieldName(LayerField::Generations), LayerField::Generations},
                                   {layerFieldName(LayerField::Distance), LayerField::Distance}},
                                  "a layer field", "curved layers follow the growth distance, steps or generations")),
      onlyWith(Method::Multidir,
               choice<SearchScheme>("multidir.scheme", [](S& s) -> SearchScheme& { return s.multidir.scheme; },
                                    {{searchSchemeName(SearchScheme::Beam), SearchScheme::Beam},
                                     {searchSchemeName(SearchScheme::Greedy), SearchScheme::Greedy},
                                     {searchSchemeName(SearchScheme::Constrained), SearchScheme::Constrained}},
                                      "a search scheme", "plane search: beam-guided, greedy or constrained greedy")),
      onlyWith(Method::Multidir,
               choice<MultidirDof>("multidir.dof", [](S& s) -> MultidirDof& { return s.multidir.dof; },
                                   {{"auto", MultidirDof::Auto}, {"4dof", MultidirDof::FourDof},
                                    {"5dof", MultidirDof::FiveDof}},
                                   "a mode", "auto (rotary4: 4dof about its A axis, else 5dof), 4dof or 5dof")),
      onlyWith(Method::Geodesic,
               choice<TraversalKind>("geodesic.sequence", [](S& s) -> TraversalKind& { return s.geodesic.sequence; },
                                     {{"a3", TraversalKind::A3}, {"lpt", TraversalKind::LPT},
                                      {"dpt", TraversalKind::DPT}},
                                     "a print sequence", "print order: a3 (Algorithm 3), lpt or dpt", {}, true)),
      onlyWith(Method::Geodesic,
               number("geodesic.align_passes", [](S& s) -> double& { return s.geodesic.alignPasses; }, 0, 100,
                      "passes", "smoothing of the heat's directions: aligns the layers where fronts merge (0 = the paper)")),
      onlyWith(Method::Geodesic,
               number("geodesic.align_retry_passes", [](S& s) -> double& { return s.geodesic.alignRetryPasses; }, 0,
                      100, "passes",
                      "where align_passes leaves tool path out, slice again with this many and keep the attempt "
                      "leaving less out (0 = no retry)")),
      onlyWith(Method::Geodesic,
               number("geodesic.heat_time", [](S& s) -> double& { return s.geodesic.heatTime; }, 0.1, 1000, "h^2",
                      "heat-method time step over the squared mean tet edge (1 = the paper; longer aligns "
                      "the layers where fronts merge: fewer tool paths left out)")),
      onlyWith(Method::Geodesic, boolean("geodesic.remesh", [](S& s) -> bool& { return s.geodesic.remesh; },
                                         "isotropic remeshing and smoothing of the layers")),
      machineJsonSpec(),
      axisLettersSpec(),
      thumbnailsSpec(),
      // Not listed: a program from a repaired mesh can only have been made with repair = auto
      // (none refuses the mesh), and the report lists the repairs.
      unlisted(choice<RepairMode>("repair", [](S& s) -> RepairMode& { return s.repair; },
                                  {{"auto", RepairMode::Auto}, {"none", RepairMode::None}},
                                  "a repair mode",
                                  "auto: close holes, split non-manifold edges and vertices, drop debris "
                                  "when the mesh does not bound a solid (methods that slice one); none: "
                                  "refuse such a mesh")),
      // Not listed: it decides whether the program is delivered, not what it holds.
      unlisted(choice<VerifyMode>("verify", [](S& s) -> VerifyMode& { return s.verify; },
                                  {{"auto", VerifyMode::Auto}, {"refuse", VerifyMode::Refuse},
                                   {"warn", VerifyMode::Warn}, {"off", VerifyMode::Off}},
                                  "a verify mode",
                                  "simulate the program as `omnislice verify` does: refuse it when unsound, "
                                  "deliver it with a warning, or not simulate (auto: refuse for multi-axis "
                                  "methods, off for planar)")),
      // Not listed: how the work is spread, not what the program holds.
      unlisted(integer("threads", [](S& s) -> int& { return s.threads; }, 0, 256, "threads",
                       "threads for the loops that run side by side: method = auto's candidates (1 = "
                       "one after another, where a candidate that cannot win stops before its check), "
                       "the curved layers' spirals (0 = every core; the wasm build runs one; the "
                       "program is the same on any number)")),
      unlisted(number("memory_mb", [](S& s) -> double& { return s.memoryMb; }, 16, 1e7, "MB",
                      "memory budget: a structure the job needs (voxel grid, tet mesh, machine motion, "
                      "verify's samples) estimated larger than this is refused before it is allocated "
                      "(out_of_memory); the wasm heap ends at 4096 MB")),
      // Not listed either: the delivered program's header lists the settings it was made with.
      unlisted(integer("verify_attempts", [](S& s) -> int& { return s.verifyAttempts; }, 1, 10, "programs",
                       "when the check finds a program unsound, make it again with the remedies the slicer "
                       "can apply itself (voxel: another smoothing of the layer field; geodesic: thinner "
                       "layers at the surface; multidir: a stricter self-supporting angle; voxel and geodesic, "
                       "last: support fins under beads over air) and deliver "
                       "the first sound one; at most this many programs (1 = no second attempt)")),
  };
  return t;
}

}  // namespace

const std::vector<SettingSpec>& settingSpecs() {
  static const std::vector<SettingSpec> table = makeTable();
  return table;
}

}  // namespace omnislice
