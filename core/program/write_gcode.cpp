// SPDX-License-Identifier: MIT
// G-code writer (cartesian3, rotary4, table5) and the parts shared with the robot writer.
//
// Dialects (PROGRAM-FORMAT.md leaves start code to the writer; the differences are kept small):
//   marlin  : G21, G90, M82, M140/M104 then M190/M109, M107, G28, G92 E0; feed semantics "xyz".
//             Part cooling fan: M106 S<0-255> / M107 before the extruding move that changes it
//             (ProgramInfo fan fields), M107 at the end; all three dialects read M106 S0-255.
//   reprap  : as marlin with T0 first (RepRapFirmware extrudes only with a selected tool);
//             feed semantics "combined".
//   klipper : as marlin without G21 (Klipper is always in millimetres and does not know G21);
//             standard commands only (no PRINT_START macro, whose name and arguments are the
//             user's); feed semantics "xyz".
// Feed: F = distance / planned duration, the distance measured on the planned values (a reader
// measuring on the written values recovers the planned time to the rounding of the coordinates): "xyz" = machine XYZ length, or the
// rotary change in degrees for pure rotations; "combined" = sqrt(XYZ^2 + rotary^2) with degrees
// counted as mm; moves without axis motion (retracts) use |E|.
// 3+2 check: between the last extruding move of one part and the first extruding move of the
// next, a move that changes a rotary value must start and end with the filament retracted and
// the machine Z at or above the safe height (machine.safeZ when declared, otherwise the highest
// machine Z of the extruding moves written so far); writeProgram refuses the path otherwise.
// Rotations within a part (curved layers) are not restricted.
#include "program/write_gcode.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <set>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "motion/plan_motion.h"
#include "machine/machine_json.h"
#include "program/program_text.h"
#include "program/thumbnail.h"

namespace omnislice {

namespace {


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

// Shortest round-trippable-enough text for header numbers.
std::string num(double v) { return formatNumber("%.10g", v); }

std::string utcNow() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

bool finite3(const Eigen::Vector3d& v) { return v.allFinite(); }

bool extrudingKind(MoveKind k) { return k == MoveKind::Print || k == MoveKind::Support; }

}  // namespace

// ---------------------------------------------------------------- shared helpers

std::string formatNumber(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double appendFixed(std::string& out, double v, int decimals) {
  static const double kPow10[] = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  decimals = std::clamp(decimals, 0, 9);
  const double scale = kPow10[decimals];
  if (!std::isfinite(v) || !(std::abs(v) * scale < 9e15)) {  // out of the exact integer range
    char buf[400];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, std::isfinite(v) ? v : 0.0);
    out += buf;
    return std::strtod(buf, nullptr);
  }
  const long long q = std::llround(v * scale);
  unsigned long long a = q < 0 ? 0ULL - static_cast<unsigned long long>(q) : q;
  char digits[32];
  int n = 0;
  do {
    digits[n++] = char('0' + a % 10);
    a /= 10;
  } while (a > 0 || n <= decimals);
  // Into a buffer, appended once (a push_back per character cost ~10 % of writing a robot
  // program in wasm).
  char text[40];
  int len = 0;
  if (q < 0) text[len++] = '-';
  for (int i = n - 1; i >= 0; --i) {
    text[len++] = digits[i];
    if (i == decimals && decimals > 0) text[len++] = '.';
  }
  out.append(text, size_t(len));
  return q == 0 ? 0.0 : double(q) / scale;
}

std::string fixedNumber(double v, int significant) {
  if (!std::isfinite(v)) return "0";
  const double mag = v != 0 ? std::floor(std::log10(std::abs(v))) : 0.0;
  const int decimals = int(std::clamp(double(significant) - 1.0 - mag, 0.0, 12.0));
  if (decimals <= 9 && std::abs(v) < 1e12) {
    std::string out;
    appendFixed(out, v, decimals);
    if (out.find('.') != std::string::npos) {
      while (!out.empty() && out.back() == '0') out.pop_back();
      if (!out.empty() && out.back() == '.') out.pop_back();
    }
    if (out == "-0") out = "0";
    return out;
  }
  char buf[400];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string out = buf;
  if (out.find('.') != std::string::npos) {
    while (!out.empty() && out.back() == '0') out.pop_back();
    if (!out.empty() && out.back() == '.') out.pop_back();
  }
  if (out == "-0") out = "0";
  return out;
}

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

std::string programHeader(const ProgramInfo& info, const MachineProfile& machine,
                          const std::string& prefix, const char* extrusionMode,
                          const char* feedSemantics, double estimatedTimeS, double filamentMm) {
  std::string out;
  auto line = [&](const std::string& s) {
    out += prefix;
    out += s;
    out += '\n';
  };
  line("omnislice " + info.version + " " + info.method + " " +
       (info.isoDate.empty() ? utcNow() : info.isoDate));
  line("omnislice:machine " + machineJson(machine));
  std::string placement = "omnislice:placement [";
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      if (row || col) placement += ",";
      placement += num(info.placement(row, col));
    }
  }
  line(placement + "]");
  line(std::string("omnislice:extrusion {\"mode\":\"") + extrusionMode +
       "\",\"filament_diameter\":" + num(info.filamentDiameter) + "}");
  line(std::string("omnislice:feed {\"semantics\":\"") + feedSemantics + "\"}");
  // The four settings every checker needs come first, from the resolved values; the remaining
  // user settings follow (a duplicate key there is skipped: the first value is the effective one).
  const std::set<std::string> required = {"layer_height", "line_width", "nozzle_diameter",
                                          "filament_diameter"};
  line("omnislice:setting layer_height = " + num(info.layerHeight));
  line("omnislice:setting line_width = " + num(info.lineWidth));
  line("omnislice:setting nozzle_diameter = " + num(machine.nozzle.diameter));
  line("omnislice:setting filament_diameter = " + num(info.filamentDiameter));
  for (const auto& kv : info.settings) {
    if (required.count(kv.first)) continue;
    std::string key = kv.first, value = kv.second;
    for (std::string* s : {&key, &value}) {
      for (char& c : *s) {
        if (c == '\n' || c == '\r') c = ' ';
      }
    }
    line("omnislice:setting " + key + " = " + value);
  }
  line("estimated printing time (normal mode) = " + durationText(estimatedTimeS));
  line("filament used [mm] = " + formatNumber("%.2f", filamentMm));
  const double filamentArea = kPi * 0.25 * info.filamentDiameter * info.filamentDiameter;
  line("filament used [cm3] = " + formatNumber("%.2f", filamentMm * filamentArea / 1000.0));
  return out;
}

Outcome checkMachinePath(const MachinePath& path, const ProgramInfo& info) {
  Outcome r;
  auto fail = [&](const std::string& msg) {
    r.status = Status::InvalidOption;
    r.message = msg;
    return r;
  };
  if (!path.ok()) return fail("machine path was not planned: " + path.message);
  const MachineProfile& machine = path.machine;
  const int n = machineAxisCount(machine.kind);
  if (!info.placement.allFinite()) return fail("placement matrix has non-finite entries");
  const double headerValues[] = {info.filamentDiameter, info.layerHeight, info.lineWidth,
                                 machine.nozzle.diameter};
  for (double v : headerValues) {
    if (!std::isfinite(v) || v <= 0) {
      return fail("filament diameter, layer height, line width and nozzle diameter must be > 0");
    }
  }
  if (!std::isfinite(info.nozzleTemperature) || !std::isfinite(info.bedTemperature) ||
      !std::isfinite(info.acceleration) || info.acceleration < 0 ||
      !std::isfinite(info.junctionDeviation) || info.junctionDeviation < 0 ||
      !std::isfinite(info.extruderAnalogPerMmS) || info.extruderAnalogPerMmS <= 0) {
    return fail("temperatures, acceleration and junction deviation must be finite (acceleration and "
                "junction deviation >= 0), the extruder analog scale > 0");
  }
  for (double pct : {info.fanPercent, info.bridgeFanPercent}) {
    if (!(pct >= 0 && pct <= 100)) return fail("fan speeds must be in 0..100 %");
  }
  if (info.fanOffLayers < 0) return fail("fan_off_layers must be >= 0");
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(path.start[i])) return fail("start values are not finite");
  }
  for (size_t k = 0; k < path.moves.size(); ++k) {
    const MachineMove& m = path.moves[k];
    const std::string at = "move " + std::to_string(k);
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(m.values[i])) return fail(at + " has a non-finite machine value");
    }
    if (!finite3(m.tip) || !finite3(m.axis) || !std::isfinite(m.filament) ||
        !std::isfinite(m.durationS) || m.durationS < 0) {
      return fail(at + " has a non-finite tip, axis, filament or duration");
    }
    Eigen::Vector3d tip, axis;
    if (!forwardMap(machine, m.values, tip, axis)) {
      return fail(at + ": the forward map cannot take its machine values");
    }
    const double tipError = (tip - m.tip).norm();
    const double axisError = (axis - m.axis.normalized()).norm();
    if (tipError > 1e-3 || axisError > 1e-4) {
      return fail(at + ": its tip / axis differ from the forward map of its machine values by " +
                  formatNumber("%.3g", tipError) + " mm / " + formatNumber("%.3g", axisError));
    }
  }
  return r;
}

void pathTotals(const MachinePath& path, double& timeS, double& filamentMm) {
  double sum = 0;
  filamentMm = 0;
  for (const MachineMove& m : path.moves) {
    sum += m.durationS;
    if (m.filament > 0) filamentMm += m.filament;
  }
  timeS = path.stats.estimatedTimeS > 0 ? path.stats.estimatedTimeS : sum;
}

// ---------------------------------------------------------------- names

const char* gcodeDialectName(GcodeDialect d) {
  switch (d) {
    case GcodeDialect::Marlin: return "marlin";
    case GcodeDialect::RepRap: return "reprap";
    case GcodeDialect::Klipper: return "klipper";
  }
  return "marlin";
}

bool parseGcodeDialect(const std::string& text, GcodeDialect& out) {
  for (GcodeDialect d : {GcodeDialect::Marlin, GcodeDialect::RepRap, GcodeDialect::Klipper}) {
    if (text == gcodeDialectName(d)) {
      out = d;
      return true;
    }
  }
  return false;
}

const char* robotFormatName(RobotFormat f) {
  switch (f) {
    case RobotFormat::UrScript: return "urscript";
    case RobotFormat::Rapid: return "rapid";
    case RobotFormat::Krl: return "krl";
    case RobotFormat::Csv: break;
  }
  return "csv";
}

bool parseRobotFormat(const std::string& text, RobotFormat& out) {
  for (RobotFormat f : {RobotFormat::Csv, RobotFormat::UrScript, RobotFormat::Rapid, RobotFormat::Krl}) {
    if (text == robotFormatName(f)) {
      out = f;
      return true;
    }
  }
  return false;
}

const char* programExtension(MachineKind kind, RobotFormat robotFormat) {
  if (kind != MachineKind::Robot6) return "gcode";
  switch (robotFormat) {
    case RobotFormat::UrScript: return "script";
    case RobotFormat::Rapid: return "mod";   // an ABB RAPID program module
    case RobotFormat::Krl: return "src";     // a KUKA KRL source file
    case RobotFormat::Csv: break;
  }
  return "csv";
}

// ---------------------------------------------------------------- G-code

namespace {

WriteProgramResult writeGcodeProgram(const MachinePath& path, const ProgramInfo& info) {
  WriteProgramResult r;
  auto fail = [&](const std::string& msg) {
    WriteProgramResult f;
    f.status = Status::InvalidOption;
    f.message = msg;
    return f;
  };
  const MachineProfile& machine = path.machine;
  const std::vector<std::string> letters = gcodeAxisLetters(machine);
  const int n = int(letters.size());
  const bool combined = info.dialect == GcodeDialect::RepRap;
  pathTotals(path, r.estimatedTimeS, r.filamentMm);

  std::string& out = r.text;
  out.reserve(1024 + path.moves.size() * (40 + 12 * n));
  auto line = [&](const std::string& s) {
    out += s;
    out += '\n';
  };
  out += programHeader(info, machine, "; ", "absolute", combined ? "combined" : "xyz",
                       r.estimatedTimeS, r.filamentMm);
  line(std::string("; omnislice:dialect ") + gcodeDialectName(info.dialect));
  for (const ProgramThumbnail& t : info.thumbnails) out += thumbnailBlock(t.png, t.width, t.height, "; ");

  // ---- start code ----
  if (info.dialect != GcodeDialect::Klipper) line("G21 ; millimetres");
  line("G90 ; absolute positioning");
  line("M82 ; absolute extrusion");
  if (info.dialect == GcodeDialect::RepRap) line("T0 ; select the tool");
  if (info.bedTemperature > 0) line("M140 S" + formatNumber("%.0f", info.bedTemperature));
  if (info.nozzleTemperature > 0) line("M104 S" + formatNumber("%.0f", info.nozzleTemperature));
  if (info.bedTemperature > 0) line("M190 S" + formatNumber("%.0f", info.bedTemperature));
  if (info.nozzleTemperature > 0) line("M109 S" + formatNumber("%.0f", info.nozzleTemperature));
  line("M107 ; part cooling fan off");
  line("G28 ; home");
  line("G92 E0");

  // Values as written (re-read from their text), so F matches what a reader measures.
  MachineValues written{};
  auto words = [&](const MachineValues& v, MachineValues& as) {
    std::string s;
    for (int i = 0; i < n; ++i) {
      s += ' ';
      s += letters[i];
      as[i] = appendFixed(s, v[i], i < 3 ? 3 : 5);  // "-0.000" comes out as "0.000"
    }
    return s;
  };
  auto distance = [&](const MachineValues& a, const MachineValues& b) {
    double lin = 0, rot = 0;
    for (int i = 0; i < n; ++i) {
      const double d = b[i] - a[i];
      (i < 3 ? lin : rot) += d * d;
    }
    if (combined) return std::sqrt(lin + rot);
    return lin > 0 ? std::sqrt(lin) : std::sqrt(rot);
  };
  MachineValues writtenRaw = path.start;  // planned values of the last move written
  std::string lastF;      // F text last written
  double lastFValue = 0;  // the feed it was written for
  auto eText = [](double value) {
    std::string t;
    appendFixed(t, value, 5);
    return t;
  };
  auto feedWord = [&](double f) -> std::string {
    // 7 significant digits: the planned time comes back to 1e-7 even for the slow XYZ feeds of
    // mostly rotary moves ("xyz" semantics).
    if (!(f > 0) || !std::isfinite(f)) return "";
    // A feed within 1e-5 of the last one written keeps it (the planned time changes by at most
    // that share): planned durations differ from move to move only by the rounding of the
    // written coordinates, and repeating F on every line doubles the writing time.
    if (lastFValue > 0 && std::abs(f - lastFValue) <= 1e-5 * lastFValue) return "";
    const std::string text = fixedNumber(f, 7);
    lastFValue = f;
    if (text == lastF) return "";
    lastF = text;
    return " F" + text;
  };

  // Travel to the start values (the park pose of the plan) at the F of the first travel.
  {
    double travelF = 150 * 60;
    MachineValues prev = path.start, scratch{};
    words(path.start, prev);
    for (const MachineMove& m : path.moves) {
      MachineValues w{};
      words(m.values, w);
      const double d = distance(prev, w);
      if (m.kind == MoveKind::Travel && m.durationS > 0 && d > 0) {
        travelF = d / m.durationS * 60;
        break;
      }
      prev = w;
    }
    // From home (every value 0 after G28) no rotary axis turns faster than it may.
    const std::vector<std::string> names = machineAxisNames(machine.kind);
    MachineValues home{};
    const double d = distance(home, path.start);
    double seconds = d > 0 ? d / (travelF / 60) : 0;
    for (int i = 3; i < n; ++i) {
      const auto dyn = machine.axisDynamics.find(names[size_t(i)]);
      if (dyn != machine.axisDynamics.end() && dyn->second.velocity > 0) {
        seconds = std::max(seconds, std::abs(path.start[i]) / dyn->second.velocity);
      }
    }
    if (d > 0 && seconds > 0) travelF = d / seconds * 60;
    line("G0" + words(path.start, written) + feedWord(travelF));
    (void)scratch;
  }

  ProgramMarkers markers(path);
  // Part cooling fan: 0..255 as M106 writes it; off until fanOffLayers (part, layer) pairs with
  // extrusion have begun.
  auto fanValue = [](double pct) { return static_cast<int>(std::lround(pct * 255 / 100)); };
  int fanNow = 0;                  // the start code switched it off
  int layersBegun = 0;             // (part, layer) pairs with extrusion so far
  std::pair<int32_t, int32_t> lastExtrudingLayer{INT32_MIN, INT32_MIN};
  bool retracted = false;
  bool printed = false;
  int32_t lastPrintedPart = 0;
  double maxPrintedZ = -std::numeric_limits<double>::infinity();
  double e = 0;  // absolute E, accumulated
  for (size_t k = 0; k < path.moves.size(); ++k) {
    const MachineMove& m = path.moves[k];
    markers.before(
        m, [&](const std::string& text) { line("; " + text); },
        [&](Feature f) {
          line(std::string("; omnislice:feature ") + featureName(f));
          line(std::string(";TYPE:") + typeName(f));
        });
    const bool extruding = extrudingKind(m.kind);
    if (extruding && m.filament > 0) {
      if (std::make_pair(m.part, m.layer) != lastExtrudingLayer) {
        lastExtrudingLayer = {m.part, m.layer};
        ++layersBegun;
      }
      const int fan = layersBegun <= info.fanOffLayers ? 0
                      : fanValue(m.feature == Feature::Bridge ? info.bridgeFanPercent : info.fanPercent);
      if (fan != fanNow) {
        line(fan > 0 ? "M106 S" + std::to_string(fan) : std::string("M107"));
        fanNow = fan;
      }
    }
    MachineValues next{};
    const std::string axisWords = words(m.values, next);
    bool moved = false, rotated = false;
    for (int i = 0; i < n; ++i) {
      if (next[i] != written[i]) {
        moved = true;
        if (i >= 3) rotated = true;
      }
    }
    // 3+2 rule between parts (see the file comment).
    if (rotated && printed && m.part != lastPrintedPart) {
      const double safe = machine.safeZ > 0 ? machine.safeZ : maxPrintedZ;
      if (!retracted || std::min(written[2], next[2]) < safe - 1e-3) {
        return fail("move " + std::to_string(k) + " rotates between parts " +
                    std::to_string(lastPrintedPart) + " and " + std::to_string(m.part) +
                    (retracted ? " below the safe height " + formatNumber("%.3f", safe) + " mm"
                               : " without a retract first"));
      }
    }
    // F from the planned (unrounded) values: equal planned speeds give equal F words ("F1200",
    // not "F1199.744"). Where the rounding of the written coordinates changes the distance a
    // reader measures by more than 0.1 % (short moves; mostly rotary ones whose few microns of
    // XYZ round away, when "xyz" semantics measure the degrees instead), F comes from the
    // written values, so the firmware takes the planned time and no axis runs faster than
    // planned (a replay of the program measured the C axis at 1.07-1.14 x its limit, and a
    // voxel program 12 % over its estimate, before).
    const double dist = distance(writtenRaw, m.values);
    const double measured = moved ? distance(written, next) : 0.0;
    double f = -1;
    if (m.durationS > 0) {
      const double along = measured > 0 && std::abs(measured - dist) > 1e-3 * dist ? measured : dist;
      const double d = moved ? along : std::abs(m.filament);
      if (d > 0) f = d / m.durationS * 60.0;
    } else if (!moved && (m.kind == MoveKind::Retract || m.kind == MoveKind::Unretract)) {
      f = 35 * 60;  // no planned time: a usual retraction speed
    }
    const std::string feed = f > 0 ? feedWord(f) : std::string();
    switch (m.kind) {
      case MoveKind::Travel:
        if (moved) line("G0" + axisWords + feed);
        break;
      case MoveKind::Print:
      case MoveKind::Support:
        if (!moved && m.filament == 0) break;
        e += m.filament;
        line("G1" + (moved ? axisWords : std::string()) + " E" + eText(e) + feed);
        break;
      case MoveKind::Retract:
      case MoveKind::Unretract:
        if (!moved && m.filament == 0) break;
        e += m.filament;
        line("G1" + (moved ? axisWords : std::string()) + " E" + eText(e) + feed);
        break;
    }
    if (m.filament < 0) retracted = true;
    if (m.filament > 0) retracted = false;
    if (extruding && m.filament > 0) {
      printed = true;
      lastPrintedPart = m.part;
      maxPrintedZ = std::max(maxPrintedZ, next[2]);
    }
    written = next;
    writtenRaw = m.values;
  }

  // ---- end code: retract, lift, heaters off, motors off ----
  line("; omnislice:end");
  if (!retracted) {
    e -= 1.0;
    line("G1 E" + formatNumber("%.5f", e) + feedWord(40 * 60));
  }
  double liftZ = written[2] + 10.0;
  auto zl = machine.axisLimits.find("Z");
  if (zl != machine.axisLimits.end()) liftZ = std::min(liftZ, zl->second.second);
  liftZ = std::max(liftZ, written[2]);
  MachineValues lifted = written;
  lifted[2] = liftZ;
  MachineValues unused{};
  line("G0" + words(lifted, unused) + feedWord(10 * 60));
  if (fanNow != 0) line("M107");
  line("M104 S0");
  line("M140 S0");
  line("M84");
  r.layers = markers.layerCount();
  return r;
}

}  // namespace

WriteProgramResult writeProgram(const MachinePath& path, const ProgramInfo& info) {
  const Outcome check = checkMachinePath(path, info);
  if (!check.ok()) {
    WriteProgramResult r;
    r.status = check.status;
    r.message = check.message;
    return r;
  }
  if (path.machine.kind == MachineKind::Robot6) return writeRobotProgram(path, info);
  return writeGcodeProgram(path, info);
}

WriteProgramResult writeGcode(const Toolpath& toolpath, const ProgramInfo& info) {
  WriteProgramResult r;
  auto fail = [&](const std::string& msg) {
    r.status = Status::InvalidOption;
    r.message = msg;
    r.text.clear();
    return r;
  };
  if (info.machine.kind != MachineKind::Cartesian3) {
    return fail("writeGcode writes cartesian3 programs only, machine kind is '" +
                std::string(machineKindName(info.machine.kind)) + "'");
  }
  if (!finite3(toolpath.start)) return fail("tool-path start is not finite");
  for (size_t i = 0; i < toolpath.moves.size(); ++i) {
    const Move& m = toolpath.moves[i];
    if (!finite3(m.position) || !std::isfinite(m.filament) || !std::isfinite(m.speed) ||
        m.speed < 0) {
      return fail("move " + std::to_string(i) + " has a non-finite position, filament or speed");
    }
    if (extrudingKind(m.kind) &&
        (!m.axis.allFinite() || (m.axis.normalized() - Eigen::Vector3d::UnitZ()).norm() > 1e-6)) {
      return fail("move " + std::to_string(i) +
                  " has a nozzle axis other than +Z, which a cartesian3 machine cannot print");
    }
  }
  MotionOptions options;
  options.acceleration = info.acceleration;
  options.junctionDeviation = info.junctionDeviation;
  const MachinePath path = planMachineMotion(toolpath, info.machine, options);
  if (!path.ok()) {
    r.status = path.status;
    r.message = path.message;
    return r;
  }
  return writeProgram(path, info);
}

}  // namespace omnislice
