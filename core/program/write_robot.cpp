// SPDX-License-Identifier: MIT
// robot6 writers: the joint CSV (canonical) and URScript generated from the same moves.
//
// CSV: header comments (`# `), then `# q1,q2,q3,q4,q5,q6,e,f,kind`, then one row per move:
// joints in radians (%.9f), e = filament mm of this move (relative; < 0 retract), f = tip speed
// along the part in mm/s (part-frame length of the joint-linear move / planned duration; 0 when
// the tip does not move), kind = print | travel | support (retracts and unretracts are travel rows
// with e != 0 and no joint change). The first row is the start (park) pose: the pose before it is
// itself, so it moves nothing. Part, layer and feature markers are comment lines between rows.
//
// URScript: the same header, `def omnislice_program():`, one `movej(q, t=T)` per move (movej
// interpolates linearly in joint space, as the format requires; T = planned duration), the
// extruder driven by analog output 0: `set_analog_out(0, v)` with v = extruderAnalogPerMmS x
// filament feed in mm/s (negative while retracting), holding until the next set_analog_out;
// filament-only moves are `sleep(T)` at the current rate. `end`, then `omnislice_program()`.
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include "kinematics/kinematics.h"
#include "program/interpolate_machine_move.h"
#include "machine/machine_json.h"
#include "program/program_text.h"

namespace omnislice {

namespace {

const char* rowKind(MoveKind k) {
  if (k == MoveKind::Print) return "print";
  if (k == MoveKind::Support) return "support";
  return "travel";
}

std::string num(double v) { return formatNumber("%.10g", v); }

}  // namespace

WriteProgramResult writeRobotProgram(const MachinePath& path, const ProgramInfo& info) {
  WriteProgramResult r;
  auto fail = [&](const std::string& msg) {
    WriteProgramResult f;
    f.status = Status::InvalidOption;
    f.message = msg;
    return f;
  };
  if (info.robotFormat == RobotFormat::Rapid || info.robotFormat == RobotFormat::Krl) {
    return writeControllerProgram(path, info);
  }
  const MachineProfile& machine = path.machine;
  const bool script = info.robotFormat == RobotFormat::UrScript;
  pathTotals(path, r.estimatedTimeS, r.filamentMm);
  std::string& out = r.text;
  out.reserve(2048 + path.moves.size() * (script ? 120 : 100));
  auto line = [&](const std::string& s) {
    out += s;
    out += '\n';
  };
  out += programHeader(info, machine, "# ", "relative", "part_tip", r.estimatedTimeS, r.filamentMm);
  const std::string indent = script ? "  " : "";
  if (script) {
    line("# omnislice:extruder {\"command\":\"set_analog_out\",\"port\":0,\"per_mm_s\":" +
         num(info.extruderAnalogPerMmS) + "}");
    line("# The extruder feed follows analog output 0: set_analog_out(0, v) with v = " +
         num(info.extruderAnalogPerMmS) + " per mm/s of filament (negative while retracting),");
    line("# held until the next set_analog_out. movej moves linearly in joint space in t seconds.");
    line("def omnislice_program():");
  } else {
    line("# q1,q2,q3,q4,q5,q6,e,f,kind");
  }

  MachineValues written{};
  MachineValues cachedValues{};  // forwardMap(cachedValues) = (cachedTip, cachedAxis) when haveCached
  Eigen::Vector3d cachedTip, cachedAxis;
  bool haveCached = false;
  auto joints = [&](const MachineValues& v, MachineValues& as, const char* sep) {
    std::string s;
    for (int i = 0; i < 6; ++i) {
      if (i) s += sep;
      as[i] = appendFixed(s, v[i], 9);
    }
    return s;
  };
  double rate = 0;  // URScript: current analog value
  auto setRate = [&](double filamentPerS) {
    const std::string v = fixedNumber(filamentPerS * info.extruderAnalogPerMmS, 9);
    const double value = std::strtod(v.c_str(), nullptr);
    if (value == rate) return;
    rate = value;
    line(indent + "set_analog_out(0, " + v + ")");
  };
  if (script) {
    line(indent + "set_analog_out(0, 0)");
    line(indent + "movej([" + joints(path.start, written, ", ") + "], a=1.4, v=1.05)");
  } else {
    line(joints(path.start, written, ",") + ",0.000000,0.000000,travel");
  }

  ProgramMarkers markers(path);
  for (size_t k = 0; k < path.moves.size(); ++k) {
    const MachineMove& m = path.moves[k];
    markers.before(
        m, [&](const std::string& text) { line(indent + "# " + text); },
        [&](Feature f) { line(indent + "# omnislice:feature " + featureName(f)); });
    MachineValues next{};
    const std::string q = joints(m.values, next, script ? ", " : ",");
    const bool moved = next != written;
    if (!moved && m.filament == 0) continue;
    if (script) {
      if (!moved) {
        const double t = m.durationS > 0 ? m.durationS : std::abs(m.filament) / 35.0;
        setRate(m.filament / t);
        line(indent + "sleep(" + fixedNumber(t, 9) + ")");
      } else if (m.durationS > 0) {
        setRate(m.filament / m.durationS);
        line(indent + "movej([" + q + "], t=" + fixedNumber(m.durationS, 9) + ")");
      } else {
        if (m.filament != 0) {
          return fail("move " + std::to_string(k) + " feeds filament without a planned duration");
        }
        setRate(0);
        line(indent + "movej([" + q + "], a=1.4, v=1.05)");
      }
    } else {
      double f = 0;
      if (moved && m.durationS > 0) {
        // The tip path's length as the reader replays it (interpolateMachineMove), from the
        // forward maps of the values as written (the previous row's kept).
        auto unmapped = [&] { return "move " + std::to_string(k) + ": machine values cannot be mapped to the part frame"; };
        if (!(haveCached && cachedValues == written) &&
            !forwardMap(machine, written, cachedTip, cachedAxis)) {
          return fail(unmapped());
        }
        Eigen::Vector3d tipNext, axisNext;
        if (!forwardMap(machine, next, tipNext, axisNext)) return fail(unmapped());
        const double length =
            interpolatedTipLength(machine, written, next, cachedTip, cachedAxis, tipNext, axisNext);
        if (!(length >= 0)) return fail(unmapped());
        f = length / m.durationS;
        cachedValues = next;
        cachedTip = tipNext;
        cachedAxis = axisNext;
        haveCached = true;
      }
      // appendFixed, not snprintf (musl formats through long double, emulated in wasm).
      std::string row = q;
      row += ',';
      appendFixed(row, m.filament, 8);
      row += ',';
      row += fixedNumber(f, 9);
      row += ',';
      row += rowKind(m.kind);
      line(row);
    }
    written = next;
  }
  if (script) {
    line(indent + "# omnislice:end");
    line(indent + "set_analog_out(0, 0)");
    line("end");
    line("omnislice_program()");
  } else {
    line("# omnislice:end");
  }
  r.layers = markers.layerCount();
  return r;
}

}  // namespace omnislice
