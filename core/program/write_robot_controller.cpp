// SPDX-License-Identifier: MIT
// robot6 programs for the arm's own controller, generated from the same moves as the joint CSV
// (write_robot.cpp): ABB RAPID and KUKA KRL. Joint values are the controller's angles in degrees:
// jointSigns[i] x q_i (the DH table's theta offsets put q = 0 at the controller's zero), written
// with 6 decimals. Both interpolate each move in joint space, as the format requires.
//
// RAPID (.mod): `MODULE OmnislicePrint` (a module file begins with it), the header as `! `
// comments, `PROC main()`. Each move `MoveAbsJ [[a1,...,a6],[9E9,...]], v1000\T:=T, z0, tool0;`
// (\T: the move takes T seconds, the planned duration; z0: the smallest zone, so the arm does not
// stop at every point); travel without a planned duration at v200. The extruder follows analog
// output aoExtruder: `SetAO aoExtruder, v;` with v = per_mm_s x filament feed in mm/s (negative
// while retracting), before the move it drives; filament-only moves (retract, unretract) are
// `WaitTime \InPos, 0;` (the arm at rest), `SetAO`, `WaitTime T;`.
//
// KRL (.src): the header as `; ` comments, `DEF omnislice_program()`. Each move
// `PTP {A1 a1, ..., A6 a6} C_PTP` after `BAS(#VEL_PTP, p)` when p changes: a synchronous PTP
// move takes max_i |delta a_i| / (p % of axis i's speed) (the leading axis at its programmed
// speed, ramps aside), so p is the integer percentage that gives the planned duration, rounded
// down (the move never runs faster than planned; at least 1 %), and the extruder value is set
// for the duration the move really takes. The extruder follows $ANOUT[1] (normalised: 1.0 =
// 10 V), set path-synchronously at the start of the move it drives:
// `TRIGGER WHEN DISTANCE=0 DELAY=0 DO $ANOUT[1]=v` with v = per_mm_s x feed; filament-only moves
// are `WAIT SEC 0` (advance-run stop), `$ANOUT[1]=v`, `WAIT SEC T`.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "common/math_constants.h"
#include "program/program_text.h"

namespace omnislice {

namespace {

constexpr int kTravelPercent = 20;       // KRL: travel moves without a planned duration
constexpr const char* kRapidTravelSpeed = "v200";

}  // namespace

WriteProgramResult writeControllerProgram(const MachinePath& path, const ProgramInfo& info) {
  auto fail = [](const std::string& msg) {
    WriteProgramResult f;
    f.status = Status::InvalidOption;
    f.message = msg;
    return f;
  };
  const bool rapid = info.robotFormat == RobotFormat::Rapid;
  const MachineProfile& machine = path.machine;
  std::array<double, 6> speedDegS{};
  for (int i = 0; i < 6; ++i) {
    speedDegS[i] = machine.jointDynamics[i].velocity * 180 / kPi;
    if (!rapid && !(speedDegS[i] > 0)) {
      return fail("KRL programs need the arm's joint speeds (joint_dynamics velocity of joint " +
                  std::to_string(i + 1) + " is 0)");
    }
  }
  WriteProgramResult r;
  pathTotals(path, r.estimatedTimeS, r.filamentMm);
  const std::string comment = rapid ? "! " : "; ";
  const std::string indent = rapid ? "    " : "  ";
  // KRL's $ANOUT is normalised to +-1 (10 V): the same volts per mm/s as URScript's and RAPID's.
  const double perMmS = rapid ? info.extruderAnalogPerMmS : info.extruderAnalogPerMmS / 10;
  std::string body;
  body.reserve(1024 + path.moves.size() * 110);
  auto line = [&](const std::string& s) {
    body += indent;
    body += s;
    body += '\n';
  };

  // Controller angles of q as written (degrees, 6 decimals) and their text.
  auto angles = [&](const MachineValues& q, std::array<double, 6>& as) {
    std::string s = rapid ? "[[" : "{";
    for (int i = 0; i < 6; ++i) {
      if (i) s += rapid ? "," : ", ";
      if (!rapid) s += "A" + std::to_string(i + 1) + " ";
      as[i] = appendFixed(s, machine.jointSigns[i] * q[i] * 180 / kPi, 6);
    }
    s += rapid ? "],[9E9,9E9,9E9,9E9,9E9,9E9]]" : "}";
    return s;
  };
  double analog = 0;
  auto setAnalog = [&](double filamentPerS, bool synchronous) {
    const std::string v = fixedNumber(filamentPerS * perMmS, 9);
    const double value = std::strtod(v.c_str(), nullptr);
    if (value == analog) return;
    analog = value;
    if (rapid) {
      line("SetAO aoExtruder, " + v + ";");
    } else if (synchronous) {
      line("TRIGGER WHEN DISTANCE=0 DELAY=0 DO $ANOUT[1]=" + v);
    } else {
      line("$ANOUT[1]=" + v);
    }
  };
  int percent = 0;
  auto setPercent = [&](int p) {
    if (p == percent) return;
    percent = p;
    line("BAS(#VEL_PTP, " + std::to_string(p) + ")");
  };
  // KRL: the duration of a PTP move between written angles at p percent.
  auto krlDuration = [&](const std::array<double, 6>& from, const std::array<double, 6>& to, int p) {
    double t = 0;
    for (int i = 0; i < 6; ++i) t = std::max(t, std::abs(to[i] - from[i]) / (speedDegS[i] * p / 100.0));
    return t;
  };

  if (rapid) {
    body += "  PROC main()\n";
    line("SetAO aoExtruder, 0;");
  } else {
    body += "DEF omnislice_program()\n";
    line("BAS(#ACC_PTP, 100)");
    line("$APO.CPTP = 1");
    line("$ANOUT[1]=0");
  }
  std::array<double, 6> written{};
  {
    const std::string start = angles(path.start, written);
    if (rapid) {
      line("MoveAbsJ " + start + ", " + kRapidTravelSpeed + ", fine, tool0;");
    } else {
      setPercent(kTravelPercent);
      line("PTP " + start);
    }
  }

  ProgramMarkers markers(path);
  double extraTime = 0;  // KRL: time beyond the plan from the whole percentages
  for (size_t k = 0; k < path.moves.size(); ++k) {
    const MachineMove& m = path.moves[k];
    markers.before(
        m, [&](const std::string& text) { line(comment + text); },
        [&](Feature f) { line(comment + "omnislice:feature " + featureName(f)); });
    std::array<double, 6> next{};
    const std::string target = angles(m.values, next);
    const bool moved = next != written;
    if (!moved && m.filament == 0) continue;
    if (!moved) {
      const double t = m.durationS > 0 ? m.durationS : std::abs(m.filament) / 35.0;
      const std::string ts = fixedNumber(t, 9);
      if (rapid) {
        line("WaitTime \\InPos, 0;");
        setAnalog(m.filament / t, false);
        line("WaitTime " + ts + ";");
      } else {
        line("WAIT SEC 0");
        setAnalog(m.filament / t, false);
        line("WAIT SEC " + ts);
      }
      continue;
    }
    if (!(m.durationS > 0) && m.filament != 0) {
      return fail("move " + std::to_string(k) + " feeds filament without a planned duration");
    }
    if (rapid) {
      if (m.durationS > 0) {
        setAnalog(m.filament / m.durationS, true);
        line("MoveAbsJ " + target + ", v1000\\T:=" + fixedNumber(m.durationS, 9) + ", z0, tool0;");
      } else {
        setAnalog(0, true);
        line("MoveAbsJ " + target + ", " + kRapidTravelSpeed + ", z0, tool0;");
      }
    } else {
      int p = kTravelPercent;
      if (m.durationS > 0) {
        double need = 0;  // percent of the axis speeds that gives the planned duration
        for (int i = 0; i < 6; ++i) need = std::max(need, std::abs(next[i] - written[i]) / (speedDegS[i] * m.durationS) * 100);
        p = std::clamp(static_cast<int>(std::floor(need + 1e-9)), 1, 100);
      }
      const double t = krlDuration(written, next, p);
      if (m.durationS > 0) extraTime += t - m.durationS;
      setPercent(p);
      setAnalog(t > 0 ? m.filament / t : 0, true);
      line("PTP " + target + " C_PTP");
    }
    written = next;
  }
  line(comment + "omnislice:end");
  if (rapid) {
    line("WaitTime \\InPos, 0;");
    line("SetAO aoExtruder, 0;");
    body += "  ENDPROC\nENDMODULE\n";
  } else {
    line("WAIT SEC 0");
    line("$ANOUT[1]=0");
    body += "END\n";
  }
  r.estimatedTimeS += extraTime;
  std::string& out = r.text;
  out.reserve(body.size() + 4096);
  if (rapid) out += "MODULE OmnislicePrint\n";
  out += programHeader(info, machine, comment, "relative", "part_tip", r.estimatedTimeS, r.filamentMm);
  if (rapid) {
    out += "! omnislice:extruder {\"command\":\"SetAO\",\"signal\":\"aoExtruder\",\"per_mm_s\":" +
           fixedNumber(perMmS, 10) + "}\n";
    out += "! The extruder feed follows analog output aoExtruder: SetAO aoExtruder, v with v = " +
           fixedNumber(perMmS, 10) + " per mm/s\n! of filament (negative while retracting), set as the "
           "next MoveAbsJ starts (RAPID's prefetch may\n! set it up to one z0 zone early). Joint angles in "
           "degrees, the controller's zero and senses.\n";
  } else {
    out += "; omnislice:extruder {\"command\":\"$ANOUT\",\"port\":1,\"per_mm_s\":" + fixedNumber(perMmS, 10) +
           "}\n";
    out += "; The extruder feed follows $ANOUT[1] (1.0 = 10 V) = " + fixedNumber(perMmS, 10) +
           " per mm/s of filament (negative while\n; retracting), set by a TRIGGER as the next PTP move "
           "starts. Axis angles in degrees, the controller's zero\n; and senses; BAS(#VEL_PTP, p) sets every "
           "axis to p % of its speed (joint_dynamics).\n";
  }
  out += body;
  r.layers = markers.layerCount();
  return r;
}

}  // namespace omnislice
