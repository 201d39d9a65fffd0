// SPDX-License-Identifier: MIT
#include "program/write_gcode.h"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <algorithm>
#include <climits>
#include <set>

namespace omnislice {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Marlin-style names host previews understand (`;TYPE:` lines, written next to the omnislice ones).
const char* typeName(Feature f) {
  switch (f) {
    case Feature::WallOuter: return "WALL-OUTER";
    case Feature::WallInner: return "WALL-INNER";
    case Feature::Skin: return "SKIN";
    case Feature::Infill: return "FILL";
    case Feature::Support: return "SUPPORT";
    case Feature::Bridge: return "BRIDGE";
    case Feature::None: return "";
  }
  return "";
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Shortest round-trippable-enough text for header numbers.
std::string num(double v) { return fmt("%.10g", v); }

std::string utcNow() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// "1h 2m 3s" with leading zero units left out ("2m 3s", "3s").
std::string durationText(double seconds) {
  long s = std::lround(std::max(0.0, seconds));
  const long h = s / 3600, m = (s % 3600) / 60;
  s %= 60;
  std::string out;
  if (h > 0) out += std::to_string(h) + "h ";
  if (h > 0 || m > 0) out += std::to_string(m) + "m ";
  out += std::to_string(s) + "s";
  return out;
}

bool finite3(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

WriteProgramResult writeGcode(const Toolpath& toolpath, const ProgramInfo& info) {
  WriteProgramResult r;
  auto fail = [&](const std::string& msg) {
    r.status = Status::InvalidOption;
    r.message = msg;
    r.text.clear();
    return r;
  };
  if (info.machine.kind != "cartesian3") {
    return fail("writeGcode writes cartesian3 programs only, machine kind is '" +
                info.machine.kind + "'");
  }
  if (!info.placement.allFinite()) return fail("placement matrix has non-finite entries");
  const double headerValues[] = {info.filamentDiameter, info.layerHeight, info.lineWidth,
                                 info.machine.nozzle.diameter};
  for (double v : headerValues) {
    if (!std::isfinite(v) || v <= 0) {
      return fail("filament diameter, layer height, line width and nozzle diameter must be > 0");
    }
  }
  if (!std::isfinite(info.nozzleTemperature) || !std::isfinite(info.bedTemperature) ||
      !std::isfinite(info.acceleration) || info.acceleration < 0) {
    return fail("temperatures and acceleration must be finite (acceleration >= 0)");
  }
  if (!finite3(toolpath.start)) return fail("tool-path start is not finite");
  for (size_t i = 0; i < toolpath.moves.size(); ++i) {
    const Move& m = toolpath.moves[i];
    if (!finite3(m.position) || !std::isfinite(m.filament) || !std::isfinite(m.speed) ||
        m.speed < 0) {
      return fail("move " + std::to_string(i) + " has a non-finite position, filament or speed");
    }
    if ((m.kind == MoveKind::Print || m.kind == MoveKind::Support) &&
        (!m.axis.allFinite() || (m.axis.normalized() - Eigen::Vector3d::UnitZ()).norm() > 1e-6)) {
      return fail("move " + std::to_string(i) +
                  " has a nozzle axis other than +Z, which a cartesian3 machine cannot print");
    }
  }

  const ToolpathStats stats = toolpathStats(toolpath, info.acceleration);
  r.estimatedTimeS = stats.estimatedTimeS;
  r.filamentMm = stats.filamentMm;

  std::string& out = r.text;
  out.reserve(64 + toolpath.moves.size() * 48);
  auto line = [&](const std::string& s) {
    out += s;
    out += '\n';
  };

  // ---- header (PROGRAM-FORMAT.md "Header") ----
  line("; omnislice " + info.version + " " + info.method + " " +
       (info.isoDate.empty() ? utcNow() : info.isoDate));
  line("; omnislice:machine " + machineJson(info.machine));
  std::string placement = "; omnislice:placement [";
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      if (row || col) placement += ",";
      placement += num(info.placement(row, col));
    }
  }
  line(placement + "]");
  line("; omnislice:extrusion {\"mode\":\"absolute\",\"filament_diameter\":" +
       num(info.filamentDiameter) + "}");
  line("; omnislice:feed {\"semantics\":\"xyz\"}");
  // The four settings every checker needs come first, from the resolved values; the remaining
  // user settings follow (a duplicate key there is skipped: the first value is the effective one).
  const std::set<std::string> required = {"layer_height", "line_width", "nozzle_diameter",
                                          "filament_diameter"};
  line("; omnislice:setting layer_height = " + num(info.layerHeight));
  line("; omnislice:setting line_width = " + num(info.lineWidth));
  line("; omnislice:setting nozzle_diameter = " + num(info.machine.nozzle.diameter));
  line("; omnislice:setting filament_diameter = " + num(info.filamentDiameter));
  for (const auto& kv : info.settings) {
    if (required.count(kv.first)) continue;
    std::string value = kv.second;
    for (char& c : value) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    line("; omnislice:setting " + kv.first + " = " + value);
  }
  line("; estimated printing time (normal mode) = " + durationText(stats.estimatedTimeS));
  line("; filament used [mm] = " + fmt("%.2f", stats.filamentMm));
  const double filamentArea = kPi * 0.25 * info.filamentDiameter * info.filamentDiameter;
  line("; filament used [cm3] = " + fmt("%.2f", stats.filamentMm * filamentArea / 1000.0));

  // ---- start code ----
  line("G21 ; millimetres");
  line("G90 ; absolute positioning");
  line("M82 ; absolute extrusion");
  if (info.bedTemperature > 0) line("M140 S" + fmt("%.0f", info.bedTemperature));
  if (info.nozzleTemperature > 0) line("M104 S" + fmt("%.0f", info.nozzleTemperature));
  if (info.bedTemperature > 0) line("M190 S" + fmt("%.0f", info.bedTemperature));
  if (info.nozzleTemperature > 0) line("M109 S" + fmt("%.0f", info.nozzleTemperature));
  line("G28 ; home");
  line("G92 E0");

  double e = 0;           // absolute E, accumulated
  double lastF = -1;      // mm/min last written
  auto feedWord = [&](double speedMmS) -> std::string {
    const double f = std::round(speedMmS * 60.0 * 1000.0) / 1000.0;
    if (f <= 0 || f == lastF) return "";
    lastF = f;
    return " F" + fmt("%.10g", f);
  };
  auto xyz = [&](const Eigen::Vector3d& p) {
    return " X" + fmt("%.3f", p.x()) + " Y" + fmt("%.3f", p.y()) + " Z" + fmt("%.3f", p.z());
  };
  // Travel to the tool-path's start position (the park position of the plan).
  {
    double travelSpeed = 0;
    for (const Move& m : toolpath.moves) {
      if (m.kind == MoveKind::Travel && m.speed > 0) {
        travelSpeed = m.speed;
        break;
      }
    }
    line("G0" + xyz(toolpath.start) + feedWord(travelSpeed > 0 ? travelSpeed : 150));
  }

  std::set<int> layersSeen;
  int currentLayer = INT32_MIN;
  Feature currentFeature = Feature::None;
  int currentPart = toolpath.moves.empty() ? 0 : toolpath.moves.front().part;
  bool retracted = false;
  Eigen::Vector3d pos = toolpath.start;
  for (const Move& m : toolpath.moves) {
    if (m.part != currentPart) {
      currentPart = m.part;
      const Eigen::Vector3d d = m.axis.normalized();
      line("; omnislice:part " + std::to_string(m.part) + " direction [" + num(d.x()) + "," +
           num(d.y()) + "," + num(d.z()) + "]");
    }
    if (m.layer != currentLayer) {
      currentLayer = m.layer;
      layersSeen.insert(m.layer);
      line("; omnislice:layer " + std::to_string(m.layer));
      currentFeature = Feature::None;  // a new layer restates its first feature
    }
    const bool extruding = m.kind == MoveKind::Print || m.kind == MoveKind::Support;
    if (extruding && m.feature != Feature::None && m.feature != currentFeature) {
      currentFeature = m.feature;
      line(std::string("; omnislice:feature ") + featureName(m.feature));
      line(std::string(";TYPE:") + typeName(m.feature));
    }
    const bool moved = (m.position - pos).norm() > 0;
    switch (m.kind) {
      case MoveKind::Travel:
        line("G0" + xyz(m.position) + feedWord(m.speed));
        break;
      case MoveKind::Print:
      case MoveKind::Support:
        e += m.filament;
        line("G1" + xyz(m.position) + " E" + fmt("%.5f", e) + feedWord(m.speed));
        break;
      case MoveKind::Retract:
      case MoveKind::Unretract:
        e += m.filament;
        line(std::string("G1") + (moved ? xyz(m.position) : std::string()) + " E" +
             fmt("%.5f", e) + feedWord(m.speed));
        break;
    }
    if (m.kind == MoveKind::Retract) retracted = true;
    if (m.kind == MoveKind::Unretract || extruding) retracted = false;
    pos = m.position;
  }

  // ---- end code: retract, lift, heaters off, motors off ----
  line("; omnislice:end");
  if (!retracted) {
    e -= 1.0;
    line("G1 E" + fmt("%.5f", e) + feedWord(40));
  }
  double liftZ = pos.z() + 10.0;
  auto zl = info.machine.axisLimits.find("Z");
  if (zl != info.machine.axisLimits.end()) liftZ = std::min(liftZ, zl->second.second);
  liftZ = std::max(liftZ, pos.z());
  line("G0 X" + fmt("%.3f", pos.x()) + " Y" + fmt("%.3f", pos.y()) + " Z" + fmt("%.3f", liftZ) +
       feedWord(10));
  line("M104 S0");
  line("M140 S0");
  line("M84");
  r.layers = static_cast<int>(layersSeen.size());
  return r;
}

}  // namespace omnislice
