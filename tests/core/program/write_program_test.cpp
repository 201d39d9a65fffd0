// SPDX-License-Identifier: MIT
// Writers of every kind and dialect, read back: the part-frame moves, headers and planned
// durations come back from the text.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <random>
#include <regex>
#include <sstream>

#include "machine_paths.h"
#include "test_toolpaths.h"
#include "motion/plan_motion.h"
#include "machine/machine_json.h"
#include "program/read_program.h"
#include "program/write_gcode.h"

namespace omnislice {
namespace {

ProgramInfo infoFor(const MachineProfile& machine) {
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.method = "test";
  info.machine = machine;
  info.layerHeight = 0.2;
  info.lineWidth = 0.45;
  info.placement << 0, -1, 0, 3, 1, 0, 0, -4, 0, 0, 1, 0.5, 0, 0, 0, 1;
  info.settings = {{"walls", "2"}};
  return info;
}

MachineProfile gcodeMachine(const std::string& kind) {
  MachineProfile m;
  EXPECT_TRUE(parseMachineKind(kind, m.kind)) << kind;
  m.name = kind + "-test";
  m.axisLimits = {{"X", {-150, 150}}, {"Y", {-150, 150}}, {"Z", {0, 200}}};
  if (kind == "rotary4") {
    m.pivot = {0, 0, 20};
    m.axisLimits["A"] = {-60, 60};
  }
  if (kind == "table5") {
    m.pivot = {5, -3, 10};
    m.axisLimits["B"] = {-90, 90};
    m.axisLimits["C"] = {-360, 360};
  }
  m.nozzle.coneHalfAngleDegrees = 35;
  m.nozzle.coneLength = 20;
  return m;
}

// Square loop of side 8 around (cx, cy) at part-frame height z, printed at fixed rotary angles.
void loop(test::MachinePathBuilder& b, double cx, double cy, double z, double a1, double a2,
          Feature f) {
  const MachineProfile& m = b.path.machine;
  const Eigen::Vector3d c[4] = {{cx - 4, cy - 4, z}, {cx + 4, cy - 4, z}, {cx + 4, cy + 4, z},
                                {cx - 4, cy + 4, z}};
  b.go(test::gcodeValues(m, c[0], a1, a2), MoveKind::Travel, 0, 150);
  b.unretract();
  for (int k = 1; k <= 4; ++k) {
    b.go(test::gcodeValues(m, c[k % 4], a1, a2), MoveKind::Print, test::MachinePathBuilder::bead(8),
         40, f);
  }
  b.retract();
}

// Two parts: part 0 (two layers at the first angles, then a print move turning the rotary axes
// while moving), a safe rotation (retract, lift, rotate, lower), part 1 at other angles.
MachinePath twoPartPath(const std::string& kind) {
  const MachineProfile m = gcodeMachine(kind);
  const double a0 = 0, c0 = kind == "table5" ? 30 : 0;
  test::MachinePathBuilder b(m, test::gcodeValues(m, {0, 0, 30}, a0, c0));
  b.retract();
  for (int l = 0; l < 2; ++l) {
    b.layer = l;
    loop(b, 0, 0, 0.2 * (l + 1), a0, c0 + 15 * l, l ? Feature::WallInner : Feature::WallOuter);
  }
  // A curved move: the rotary values change while printing (curved-layer style).
  b.layer = 2;
  b.go(test::gcodeValues(m, {-4, -4, 0.6}, a0, c0), MoveKind::Travel, 0, 150);
  b.unretract();
  const double turn1 = kind == "rotary4" ? 12 : kind == "table5" ? 8 : 0;
  const double turn2 = kind == "table5" ? 40 : 0;
  b.go(test::gcodeValues(m, {4, 3, 0.6}, a0 + turn1, c0 + turn2), MoveKind::Print,
       test::MachinePathBuilder::bead(10), 30, Feature::Infill);
  b.retract();
  // Safe rotation to part 1.
  const double a1 = kind == "rotary4" ? -35 : kind == "table5" ? 25 : 0;
  const double c1 = kind == "table5" ? 120 : 0;
  MachineValues lift = b.current();
  lift[2] = 40;
  b.go(lift, MoveKind::Travel, 0, 150);
  b.part = 1;
  MachineValues rotated = lift;
  rotated[3] = a1;
  if (kind == "table5") rotated[4] = c1;
  b.go(rotated, MoveKind::Travel, 0, 150);
  for (int l = 3; l < 5; ++l) {
    b.layer = l;
    const MachineValues over = test::gcodeValues(m, {2, 1, 0.2 * l}, a1, c1);
    MachineValues above = over;
    above[2] = 40;
    if (l == 3) b.go(above, MoveKind::Travel, 0, 150);
    loop(b, 2, 1, 0.2 * l, a1, c1, Feature::Skin);
  }
  return b.path;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// Groups of parsed pieces by source line, in order.
std::vector<std::vector<const ProgramMove*>> groups(const ParsedProgram& p) {
  std::vector<std::vector<const ProgramMove*>> g;
  for (const ProgramMove& m : p.moves) {
    if (g.empty() || g.back().front()->line != m.line) g.emplace_back();
    g.back().push_back(&m);
  }
  return g;
}

// Checks the parsed pieces of a program written from `path`: one group per moving move (after
// `skip` leading groups), tips and axes at the ends, filament sums, every piece on the replayed
// path (piece ends are the forward map of their values; the values' midpoint is within 0.01 mm of
// the chord). Returns the groups for further checks.
std::vector<std::vector<const ProgramMove*>> checkRoundTrip(const MachinePath& path,
                                                            const ParsedProgram& p, size_t skip,
                                                            double filamentTolerance) {
  const auto g = groups(p);
  size_t k = skip;
  Eigen::Vector3d prevTip;
  Eigen::Vector3d unused;
  forwardMap(path.machine, path.start, prevTip, unused);
  MachineValues prevValues = path.start;
  for (size_t i = 0; i < path.moves.size(); ++i) {
    const MachineMove& m = path.moves[i];
    if (m.values == prevValues && m.filament == 0) continue;
    EXPECT_LT(k, g.size());
    if (k >= g.size()) break;
    const auto& grp = g[k++];
    EXPECT_LT((grp.front()->from - prevTip).norm(), 1e-3) << "move " << i;
    EXPECT_LT((grp.back()->to - m.tip).norm(), 1e-3) << "move " << i;
    EXPECT_LT((grp.back()->axis - m.axis).norm(), 1e-6) << "move " << i;
    double filament = 0;
    const ProgramMove* prev = nullptr;
    for (const ProgramMove* piece : grp) {
      filament += piece->filament;
      MachineValues v{};
      std::copy(piece->axes.begin(), piece->axes.end(), v.begin());
      Eigen::Vector3d tip, axis;
      EXPECT_TRUE(forwardMap(p.machine, v, tip, axis));
      EXPECT_LT((tip - piece->to).norm(), 1e-9);
      EXPECT_LT((axis - piece->axis).norm(), 1e-9);
      if (prev) {
        EXPECT_LT((piece->from - prev->to).norm(), 1e-12);
        MachineValues a{};
        std::copy(prev->axes.begin(), prev->axes.end(), a.begin());
        Eigen::Vector3d mid;
        forwardMap(p.machine, lerpValues(a, v, 0.5), mid, axis);
        const Eigen::Vector3d ab = piece->to - piece->from;
        const double t = ab.squaredNorm() > 0
                             ? std::clamp((mid - piece->from).dot(ab) / ab.squaredNorm(), 0.0, 1.0)
                             : 0.0;
        EXPECT_LE((piece->from + t * ab - mid).norm(), 0.0101) << "move " << i;
      }
      prev = piece;
    }
    EXPECT_NEAR(filament, m.filament, filamentTolerance) << "move " << i;
    prevTip = m.tip;
    prevValues = m.values;
  }
  return g;
}

TEST(WriteProgram, GcodeKindsAndDialectsRoundTrip) {
  for (const std::string kind : {"cartesian3", "rotary4", "table5"}) {
    const MachinePath path = twoPartPath(kind);
    for (GcodeDialect dialect : {GcodeDialect::Marlin, GcodeDialect::RepRap, GcodeDialect::Klipper}) {
      SCOPED_TRACE(kind + " " + gcodeDialectName(dialect));
      ProgramInfo info = infoFor(path.machine);
      info.dialect = dialect;
      const WriteProgramResult w = writeProgram(path, info);
      ASSERT_TRUE(w.ok()) << w.message;
      EXPECT_EQ(w.layers, 5);
      const ParsedProgram p = readProgram(w.text);
      ASSERT_TRUE(p.ok()) << p.message;
      // Header facts.
      EXPECT_EQ(p.format, "gcode");
      EXPECT_EQ(p.method, "test");
      EXPECT_EQ(p.feedSemantics, dialect == GcodeDialect::RepRap ? "combined" : "xyz");
      EXPECT_EQ(machineJson(p.machine), machineJson(path.machine));
      EXPECT_EQ(p.machine.pivot, path.machine.pivot);
      EXPECT_EQ(p.machine.axisLimits, path.machine.axisLimits);
      EXPECT_TRUE(p.placement.isApprox(info.placement, 1e-12));
      EXPECT_TRUE(p.absoluteExtrusion);
      EXPECT_EQ(p.layerHeight, 0.2);
      EXPECT_EQ(p.lineWidth, 0.45);
      EXPECT_EQ(p.layerCount, 5);
      // Start code per dialect.
      const auto ls = lines(w.text);
      auto has = [&](const std::string& prefix) {
        return std::any_of(ls.begin(), ls.end(),
                           [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
      };
      EXPECT_EQ(has("G21"), dialect != GcodeDialect::Klipper);
      EXPECT_EQ(has("T0"), dialect == GcodeDialect::RepRap);
      EXPECT_TRUE(has("M109 S210") && has("M190 S60") && has("G28") && has("M82"));
      EXPECT_TRUE(has("; omnislice:part 0 direction [") && has("; omnislice:part 1 direction ["));
      EXPECT_TRUE(has(";TYPE:WALL-OUTER") && has("; omnislice:feature skin"));
      // Numbers in fixed notation only (firmware does not read exponents).
      for (const std::string& l : ls) {
        if (l.rfind("G0 ", 0) == 0 || l.rfind("G1 ", 0) == 0) {
          EXPECT_EQ(l.find_first_of("e+;"), std::string::npos) << l;
        }
      }
      // Moves: the park travel from home first, then one group per moving path move.
      const auto g = checkRoundTrip(path, p, 1, 1.1e-5);
      // F gives back the planned durations (to the rounding of the written values and of F).
      const std::vector<std::string> names = machineAxisNames(path.machine.kind);
      size_t k = 1;
      MachineValues prevValues = path.start;
      MoveAxes prevAxes = g[0].back()->axes;
      for (size_t i = 0; i < path.moves.size(); ++i) {
        const MachineMove& m = path.moves[i];
        if (m.values == prevValues && m.filament == 0) continue;
        const auto& grp = g[k++];
        const MoveAxes& end = grp.back()->axes;
        double lin = 0, rot = 0;
        for (size_t a = 0; a < end.size(); ++a) {
          const double d = end[a] - prevAxes[a];
          (a < 3 ? lin : rot) += d * d;
        }
        double dist = dialect == GcodeDialect::RepRap ? std::sqrt(lin + rot)
                      : lin > 0                       ? std::sqrt(lin)
                                                      : std::sqrt(rot);
        if (dist == 0) {
          double e = 0;
          for (const ProgramMove* piece : grp) e += piece->filament;
          dist = std::abs(e);
        }
        const double duration = dist / grp.back()->feedMmPerMin * 60.0;
        EXPECT_NEAR(duration, m.durationS, 0.01 * m.durationS) << "move " << i;
        // The E word carries the filament of the move; the reader splits it over the pieces.
        prevAxes = end;
        prevValues = m.values;
      }
      // Rotating moves were cut into pieces.
      if (kind != "cartesian3") {
        EXPECT_GT(p.moves.size(), g.size() + 10);
      }
      if (kind == "cartesian3") {
        EXPECT_EQ(p.moves.size(), g.size());
      }
      // End code: retract was already done; a lift.
      EXPECT_EQ(g.size(), k + 1);
    }
  }
}


// robot6: two parts on the UR5 test machine; part 0 flat (with a support loop and a move that
// tilts the platform while printing), part 1 tilted 30 degrees about x.
MachinePath robotPath() {
  const MachineProfile m = test::ur5TestMachine();
  MachineValues v{};
  const Eigen::Matrix3d flat = Eigen::Matrix3d::Identity();
  EXPECT_TRUE(test::robotStart(m, {0, 0, 30}, flat, v));
  test::MachinePathBuilder b(m, v);
  auto to = [&](const Eigen::Vector3d& q, const Eigen::Matrix3d& rot, MoveKind kind, double speed,
                Feature f) {
    MachineValues next{};
    EXPECT_TRUE(test::robotValues(m, q, rot, b.current(), next));
    Eigen::Vector3d from, axis;
    forwardMap(m, b.current(), from, axis);
    const double filament =
        kind == MoveKind::Travel ? 0.0 : test::MachinePathBuilder::bead((q - from).norm());
    b.go(next, kind, filament, speed, f);
  };
  auto square = [&](double z, const Eigen::Matrix3d& rot, MoveKind kind, Feature f) {
    const Eigen::Vector3d c[4] = {{-4, -4, z}, {4, -4, z}, {4, 4, z}, {-4, 4, z}};
    to(c[0], rot, MoveKind::Travel, 150, Feature::None);
    b.unretract();
    for (int k = 1; k <= 4; ++k) to(c[k % 4], rot, kind, 40, f);
    b.retract();
  };
  b.retract();
  b.layer = 0;
  square(0.2, flat, MoveKind::Support, Feature::Support);
  b.layer = 1;
  square(0.4, flat, MoveKind::Print, Feature::WallOuter);
  b.layer = 2;
  to({-4, 0, 0.6}, flat, MoveKind::Travel, 150, Feature::None);
  b.unretract();
  to({4, 0, 0.6}, test::rotDeg(0, 10).transpose(), MoveKind::Print, 30, Feature::Infill);
  b.retract();
  b.part = 1;
  const Eigen::Matrix3d tilted = test::rotDeg(0, 30).transpose();
  to({0, 0, 20}, tilted, MoveKind::Travel, 150, Feature::None);
  for (int l = 3; l < 5; ++l) {
    b.layer = l;
    square(0.2 * l, tilted, MoveKind::Print, Feature::Skin);
  }
  return b.path;
}

// Writes `path` as a robot program in `format` and reads it back: the checks every robot format
// shares (5 layers, its format name, the machine and placement carried in the header).
ParsedProgram writeAndReadRobot(const MachinePath& path, RobotFormat format, WriteProgramResult& w,
                                ProgramInfo& info) {
  info = infoFor(path.machine);
  info.robotFormat = format;
  info.extruderAnalogPerMmS = 0.25;
  w = writeProgram(path, info);
  EXPECT_TRUE(w.ok()) << w.message;
  EXPECT_EQ(w.layers, 5);
  ParsedProgram p = readProgram(w.text);
  EXPECT_TRUE(p.ok()) << p.message;
  EXPECT_EQ(p.format, robotFormatName(format));
  EXPECT_FALSE(p.absoluteExtrusion);
  EXPECT_EQ(machineJson(p.machine), machineJson(path.machine));
  EXPECT_TRUE(p.placement.isApprox(info.placement, 1e-12));
  EXPECT_EQ(p.layerCount, 5);
  return p;
}

// For each planned move with tip motion, `check(move index, planned duration, replayed duration)`,
// the replayed one from the read-back group's part-frame length / its feed. `g` from
// checkRoundTrip(): one group per move that changes the values or the filament.
template <class Check>
void forEachReplayedDuration(const MachinePath& path, const std::vector<std::vector<const ProgramMove*>>& g,
                             Check check) {
  size_t k = 0;
  MachineValues prevValues = path.start;
  for (size_t i = 0; i < path.moves.size() && k < g.size(); ++i) {
    const MachineMove& m = path.moves[i];
    if (m.values == prevValues && m.filament == 0) continue;
    const auto& grp = g[k++];
    const bool moved = m.values != prevValues;
    prevValues = m.values;
    if (!moved || !(m.durationS > 0)) continue;
    double len = 0;
    for (const ProgramMove* piece : grp) len += (piece->to - piece->from).norm();
    if (len < 1e-6) continue;  // no tip motion: no speed to give back
    check(i, m.durationS, len / (grp.back()->feedMmPerMin / 60.0));
  }
  EXPECT_EQ(k, g.size());
}

TEST(WriteProgram, RobotCsvAndUrScriptRoundTrip) {
  const MachinePath path = robotPath();
  ASSERT_GT(path.moves.size(), 30u);
  for (RobotFormat format : {RobotFormat::Csv, RobotFormat::UrScript}) {
    SCOPED_TRACE(robotFormatName(format));
    WriteProgramResult w;
    ProgramInfo info;
    const ParsedProgram p = writeAndReadRobot(path, format, w, info);
    ASSERT_TRUE(w.ok() && p.ok());
    EXPECT_EQ(p.feedSemantics, "part_tip");
    EXPECT_EQ(p.machine.kind, MachineKind::Robot6);
    EXPECT_TRUE(p.machine.flangeToPlatform.isApprox(path.machine.flangeToPlatform, 1e-12));
    const auto ls = lines(w.text);
    ASSERT_GT(ls.size(), 20u);
    EXPECT_EQ(ls[0], std::string("# omnislice ") + OMNISLICE_VERSION + " test 2026-11-21T12:00:00Z");
    if (format == RobotFormat::Csv) {
      EXPECT_NE(std::find(ls.begin(), ls.end(), "# q1,q2,q3,q4,q5,q6,e,f,kind"), ls.end());
      EXPECT_NE(w.text.find(",support\n"), std::string::npos);
    } else {
      EXPECT_NE(std::find(ls.begin(), ls.end(), "def omnislice_program():"), ls.end());
      EXPECT_EQ(ls[ls.size() - 2], "end");
      EXPECT_EQ(ls.back(), "omnislice_program()");
      EXPECT_NE(w.text.find("set_analog_out(0, "), std::string::npos);
      for (const std::string& l : ls) {
        const size_t open = l.find('(');
        if (l[0] == '#' || open == std::string::npos) continue;
        EXPECT_EQ(l.find_first_of("eE+", open), std::string::npos) << l;  // no exponents
      }
    }
    // The first row / target is the start pose: no group for it.
    const auto g = checkRoundTrip(path, p, 0, 1e-5);
    // f gives back the planned durations: part-frame length / speed.
    forEachReplayedDuration(path, g, [](size_t i, double planned, double replayed) {
      EXPECT_NEAR(replayed, planned, 0.01 * planned) << "move " << i;
    });
  }
}

// 200 mutations of a valid program (characters from `alphabet` or NUL written over random places,
// every fourth one also truncated): each parses or fails with a line number and no moves, moves
// are always finite, and some mutations do fail.
void expectMutationsFailCleanly(const std::string& valid, const std::string& alphabet,
                                std::mt19937& rng) {
  int errors = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::string text = valid;
    std::uniform_int_distribution<size_t> at(0, text.size() - 1);
    for (int k = 0; k < 1 + trial % 5; ++k) text[at(rng)] = alphabet.c_str()[rng() % (alphabet.size() + 1)];  // NUL too
    if (trial % 4 == 3) text.resize(at(rng));
    const ParsedProgram p = readProgram(text);
    if (!p.ok()) {
      ++errors;
      EXPECT_NE(p.message.find("line "), std::string::npos) << p.message;
      EXPECT_TRUE(p.moves.empty());
    }
    for (const ProgramMove& m : p.moves) {
      EXPECT_TRUE(m.from.allFinite() && m.to.allFinite() && m.axis.allFinite());
    }
  }
  EXPECT_GT(errors, 0);
}

TEST(WriteProgram, MutatedRobotProgramsNeverCrash) {
  const MachinePath path = robotPath();
  std::mt19937 rng(7);
  for (RobotFormat format : {RobotFormat::Csv, RobotFormat::UrScript}) {
    ProgramInfo info = infoFor(path.machine);
    info.robotFormat = format;
    const WriteProgramResult w = writeProgram(path, info);
    ASSERT_TRUE(w.ok());
    expectMutationsFailCleanly(w.text, "q,#[]()=t0.-e9\n ", rng);
  }
  MachinePath timed = path;
  for (AxisDynamics& d : timed.machine.jointDynamics) d.velocity = 1;  // KRL needs joint speeds
  for (RobotFormat format : {RobotFormat::Rapid, RobotFormat::Krl}) {
    ProgramInfo info = infoFor(timed.machine);
    info.robotFormat = format;
    const WriteProgramResult w = writeProgram(timed, info);
    ASSERT_TRUE(w.ok()) << w.message;
    expectMutationsFailCleanly(w.text, "A,;![]{}()=T:\\0.-E9\n ", rng);
  }
}

// ABB RAPID and KUKA KRL written from the UR5 test path (joint signs +1, the UR's zero) read back
// to the same print: every move's tip, axis and filament; RAPID's \T times are the planned
// durations; KRL's whole percentages of the joint speeds never make a move faster than planned.
TEST(WriteProgram, RobotRapidAndKrlRoundTrip) {
  MachinePath path = robotPath();
  {
    // KRL times its moves by percentages of the joint speeds: a profile without them is refused.
    ProgramInfo info = infoFor(path.machine);
    info.robotFormat = RobotFormat::Krl;
    const WriteProgramResult w = writeProgram(path, info);
    EXPECT_EQ(w.status, Status::InvalidOption);
    EXPECT_NE(w.message.find("joint speeds"), std::string::npos) << w.message;
  }
  for (int j = 0; j < 6; ++j) path.machine.jointDynamics[j].velocity = 0.5 + 0.1 * j;  // rad/s
  for (RobotFormat format : {RobotFormat::Rapid, RobotFormat::Krl}) {
    SCOPED_TRACE(robotFormatName(format));
    WriteProgramResult w;
    ProgramInfo info;
    const ParsedProgram p = writeAndReadRobot(path, format, w, info);
    ASSERT_TRUE(w.ok() && p.ok());
    const auto ls = lines(w.text);
    const std::string version = std::string("omnislice ") + OMNISLICE_VERSION + " test 2026-11-21T12:00:00Z";
    if (format == RobotFormat::Rapid) {
      EXPECT_EQ(ls[0], "MODULE OmnislicePrint");
      EXPECT_EQ(ls[1], "! " + version);
      EXPECT_EQ(ls.back(), "ENDMODULE");
      EXPECT_NE(w.text.find("MoveAbsJ [["), std::string::npos);
      EXPECT_NE(w.text.find("SetAO aoExtruder, "), std::string::npos);
      EXPECT_NE(w.text.find("WaitTime "), std::string::npos);  // the retracts
    } else {
      EXPECT_EQ(ls[0], "; " + version);
      EXPECT_NE(std::find(ls.begin(), ls.end(), "DEF omnislice_program()"), ls.end());
      EXPECT_EQ(ls.back(), "END");
      EXPECT_NE(w.text.find("PTP {A1 "), std::string::npos);
      EXPECT_NE(w.text.find("TRIGGER WHEN DISTANCE=0 DELAY=0 DO $ANOUT[1]="), std::string::npos);
      EXPECT_NE(w.text.find("BAS(#VEL_PTP, "), std::string::npos);
    }
    for (std::string l : ls) {
      // Statements only (comments are text), without RAPID's 9E9 (no external axis).
      l = l.substr(std::min(l.size(), l.find_first_not_of(' ')));
      if (l.empty() || l[0] == '!' || l[0] == ';') continue;
      for (size_t at; (at = l.find("9E9")) != std::string::npos;) l.erase(at, 3);
      EXPECT_FALSE(std::regex_search(l, std::regex("[0-9.][eE][-+]?[0-9]"))) << l;  // no exponents
    }
    const auto g = checkRoundTrip(path, p, 0, 1e-5);
    double planned = 0, replayed = 0;
    forEachReplayedDuration(path, g, [&](size_t i, double plan, double replay) {
      planned += plan;
      replayed += replay;
      if (format == RobotFormat::Rapid) {
        EXPECT_NEAR(replay, plan, 1e-6 * plan + 1e-9) << "move " << i;
      } else {
        EXPECT_GE(replay, plan * (1 - 1e-6)) << "move " << i;
      }
    });
    std::printf("%s: planned %.2f s, replayed %.2f s\n", robotFormatName(format), planned, replayed);
  }
}

TEST(WriteProgram, RefusesRotationBetweenPartsWithoutRetractOrLift) {
  const MachineProfile m = gcodeMachine("table5");
  ProgramInfo info = infoFor(m);
  auto build = [&](bool retract, double liftZ) {
    test::MachinePathBuilder b(m, test::gcodeValues(m, {0, 0, 30}, 0, 0));
    loop(b, 0, 0, 0.2, 0, 0, Feature::WallOuter);
    b.unretract();  // the loop ends retracted; undo that for the faulty case
    if (retract) b.retract();
    MachineValues v = b.current();
    v[2] = liftZ;
    b.go(v, MoveKind::Travel, 0, 100);
    b.part = 1;
    v[3] = 30;
    b.go(v, MoveKind::Travel, 0, 100);
    return b.path;
  };
  EXPECT_TRUE(writeProgram(build(true, 40), info).ok());
  const WriteProgramResult noRetract = writeProgram(build(false, 40), info);
  EXPECT_EQ(noRetract.status, Status::InvalidOption);
  EXPECT_NE(noRetract.message.find("without a retract"), std::string::npos) << noRetract.message;
  // Below the top of the printed loop (machine Z 0.2).
  const WriteProgramResult low = writeProgram(build(true, 0.1), info);
  EXPECT_EQ(low.status, Status::InvalidOption);
  EXPECT_NE(low.message.find("safe height"), std::string::npos) << low.message;
  // Within a part, rotations while printing are allowed (curved layers): see the round trip.
}

TEST(WriteProgram, RefusesInconsistentOrNonFinitePaths) {
  MachinePath path = twoPartPath("rotary4");
  const ProgramInfo info = infoFor(path.machine);
  ASSERT_TRUE(writeProgram(path, info).ok());
  MachinePath wrongTip = path;
  wrongTip.moves[5].tip.x() += 0.01;
  EXPECT_EQ(writeProgram(wrongTip, info).status, Status::InvalidOption);
  MachinePath nan = path;
  nan.moves[3].values[3] = std::nan("");
  EXPECT_EQ(writeProgram(nan, info).status, Status::InvalidOption);
  MachinePath negative = path;
  negative.moves[2].durationS = -1;
  EXPECT_EQ(writeProgram(negative, info).status, Status::InvalidOption);
  MachinePath failed = path;
  failed.status = Status::InvalidOption;
  EXPECT_EQ(writeProgram(failed, info).status, Status::InvalidOption);
}

TEST(WriteProgram, NamesAndExtensions) {
  GcodeDialect d;
  EXPECT_TRUE(parseGcodeDialect("klipper", d));
  EXPECT_EQ(d, GcodeDialect::Klipper);
  EXPECT_TRUE(parseGcodeDialect(gcodeDialectName(GcodeDialect::RepRap), d));
  EXPECT_EQ(d, GcodeDialect::RepRap);
  EXPECT_FALSE(parseGcodeDialect("grbl", d));
  RobotFormat f;
  EXPECT_TRUE(parseRobotFormat("urscript", f));
  EXPECT_EQ(f, RobotFormat::UrScript);
  EXPECT_TRUE(parseRobotFormat("krl", f));
  EXPECT_EQ(f, RobotFormat::Krl);
  EXPECT_TRUE(parseRobotFormat("rapid", f));
  EXPECT_EQ(f, RobotFormat::Rapid);
  EXPECT_FALSE(parseRobotFormat("fanuc", f));
  EXPECT_STREQ(programExtension(MachineKind::Robot6, RobotFormat::Rapid), "mod");
  EXPECT_STREQ(programExtension(MachineKind::Robot6, RobotFormat::Krl), "src");
  EXPECT_STREQ(robotFormatName(RobotFormat::Csv), "csv");
  EXPECT_STREQ(programExtension(MachineKind::Table5, RobotFormat::Csv), "gcode");
  EXPECT_STREQ(programExtension(MachineKind::Robot6, RobotFormat::Csv), "csv");
  EXPECT_STREQ(programExtension(MachineKind::Robot6, RobotFormat::UrScript), "script");
}

TEST(WriteProgram, MutatedGcodeOfEveryKindNeverCrashes) {
  std::mt19937 rng(99);
  for (const std::string kind : {"rotary4", "table5"}) {
    const MachinePath path = twoPartPath(kind);
    const WriteProgramResult w = writeProgram(path, infoFor(path.machine));
    ASSERT_TRUE(w.ok());
    expectMutationsFailCleanly(w.text, "GXABCE;{[0.-e9\n #", rng);
  }
}

}  // namespace
}  // namespace omnislice

namespace omnislice {
namespace {

// Times of writing and reading large programs (printed; speed is benchmarked, not asserted).
TEST(WriteProgram, LargeProgramTimes) {
  const MachineProfile m = gcodeMachine("table5");
  test::MachinePathBuilder b(m, test::gcodeValues(m, {0, 0, 5}, 0, 0));
  for (int k = 0; k < 200000; ++k) {
    const int layer = k / 2000;
    b.layer = layer;
    const double a = 2 * M_PI * (k % 2000) / 2000.0;
    b.push(test::gcodeValues(m, {20 * std::cos(a), 20 * std::sin(a), 0.2 * (layer + 1)}, 0,
                             layer * 3.0),
           MoveKind::Print, 0.002, 0.0016, Feature::WallOuter);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const WriteProgramResult w = writeProgram(b.path, infoFor(m));
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_TRUE(w.ok()) << w.message;
  const ParsedProgram p = readProgram(w.text);
  const auto t2 = std::chrono::steady_clock::now();
  ASSERT_TRUE(p.ok()) << p.message;
  EXPECT_GE(p.moves.size(), 200000u);
  std::printf("table5 200k moves: write %.2f s (%zu MB), read %.2f s (%zu pieces)\n",
              std::chrono::duration<double>(t1 - t0).count(), w.text.size() >> 20,
              std::chrono::duration<double>(t2 - t1).count(), p.moves.size());
}

TEST(WriteProgram, LargeRobotProgramTimes) {
  // 100k joint-space moves of a smooth motion (not a print: timing only).
  const MachineProfile m = test::ur5TestMachine();
  MachineValues q0{};
  ASSERT_TRUE(test::robotStart(m, {0, 0, 5}, Eigen::Matrix3d::Identity(), q0));
  test::MachinePathBuilder b(m, q0);
  for (int k = 0; k < 100000; ++k) {
    b.layer = k / 1000;
    MachineValues q = q0;
    const double s = 2 * M_PI * k / 1000.0;
    q[0] += 0.02 * std::sin(s);
    q[1] += 0.01 * std::cos(s);
    q[5] += 0.02 * std::cos(s);
    b.push(q, MoveKind::Print, 0.002, 0.01, Feature::WallOuter);
  }
  for (RobotFormat format : {RobotFormat::Csv, RobotFormat::UrScript}) {
    ProgramInfo info = infoFor(m);
    info.robotFormat = format;
    const auto t0 = std::chrono::steady_clock::now();
    const WriteProgramResult w = writeProgram(b.path, info);
    const auto t1 = std::chrono::steady_clock::now();
    ASSERT_TRUE(w.ok()) << w.message;
    const ParsedProgram p = readProgram(w.text);
    const auto t2 = std::chrono::steady_clock::now();
    ASSERT_TRUE(p.ok()) << p.message;
    EXPECT_GE(p.moves.size(), 100000u);
    std::printf("robot6 100k moves %s: write %.2f s (%zu MB), read %.2f s (%zu pieces)\n",
                robotFormatName(format), std::chrono::duration<double>(t1 - t0).count(),
                w.text.size() >> 20, std::chrono::duration<double>(t2 - t1).count(),
                p.moves.size());
  }
}

}  // namespace
}  // namespace omnislice

namespace omnislice {
namespace {

// Each malformed robot / rotary construct gives its status and names its line.
TEST(WriteProgram, MalformedRobotAndRotaryLines) {
  const MachinePath path = robotPath();
  ProgramInfo info = infoFor(path.machine);
  const std::string csv = writeProgram(path, info).text;
  info.robotFormat = RobotFormat::UrScript;
  const std::string script = writeProgram(path, info).text;
  auto lineOf = [](const std::string& text, const std::string& what) {
    const size_t at = text.find(what);
    return 1 + std::count(text.begin(), text.begin() + at, '\n');
  };
  auto expectError = [](const std::string& text, Status s, long line) {
    const ParsedProgram p = readProgram(text);
    EXPECT_EQ(p.status, s) << p.message;
    EXPECT_NE(p.message.find("line " + std::to_string(line) + ":"), std::string::npos) << p.message;
  };
  // CSV: a row with 8 fields, an unknown kind, a non-numeric joint.
  {
    const size_t row = csv.find(",print\n");
    const size_t start = csv.rfind('\n', row) + 1;
    const long line = lineOf(csv, csv.substr(start, row - start));
    std::string t = csv;
    t.replace(row, 7, ",,print\n");
    expectError(t, Status::ParseError, line);
    t = csv;
    t.replace(row, 7, ",drill\n");
    expectError(t, Status::ParseError, line);
    t = csv;
    t.replace(start, 1, "x");
    expectError(t, Status::ParseError, line);
    // Columns in another order are not guessed.
    t = csv;
    t.replace(t.find("# q1,q2"), 7, "# q2,q1");
    expectError(t, Status::UnsupportedFormat, lineOf(csv, "# q1,q2"));
  }
  // URScript: movel, a movej without its list, an unknown statement, a missing end.
  {
    const size_t mv = script.find("movej([", script.find("t="));
    const long line = lineOf(script, script.substr(mv, 40));
    std::string t = script;
    t.replace(mv, 5, "movel");
    expectError(t, Status::UnsupportedFormat, line);
    t = script;
    t.replace(mv, 7, "movej((");
    expectError(t, Status::ParseError, line);
    t = script;
    t.replace(mv, 5, "spinj");
    expectError(t, Status::ParseError, line);
    t = script.substr(0, script.rfind("end\n"));
    const ParsedProgram p = readProgram(t);
    EXPECT_EQ(p.status, Status::ParseError);
  }
  // G-code: a rotation of more than 10 turns in one move.
  {
    const MachinePath g = twoPartPath("rotary4");
    std::string t = writeProgram(g, infoFor(g.machine)).text;
    const size_t a = t.find(" A", t.find("G1 X"));
    const long line = lineOf(t, t.substr(t.rfind('\n', a) + 1, a - t.rfind('\n', a) - 1));
    t.insert(a + 2, "9999");
    expectError(t, Status::ParseError, line);
  }
}

}  // namespace
}  // namespace omnislice

namespace omnislice {
namespace {

// A two-part 3+2 tool-path planned by planMachineMotion on rotary4 and table5: the planner's
// safe rotations (retract, lift, rotate) pass the writer's 3+2 check, and the part markers carry
// each part's direction.
TEST(WriteProgram, PlannedThreePlusTwoPassesTheWriterCheck) {
  test::BoxPathOptions o;
  o.height = 1;
  Toolpath tp = test::boxToolpath(o);
  const size_t first = tp.moves.size();
  const Toolpath top = test::boxToolpath(o);
  const Eigen::Vector3d tilted(0, -std::sin(M_PI / 6), std::cos(M_PI / 6));
  for (Move m : top.moves) {
    m.part = 1;
    m.layer += 5;
    m.position.z() += 1.0;
    // The retract that ends part 0 keeps part 0's axis; part 1 starts with its travel. (A retract
    // carrying the new axis is planned as a rotation in place, which the writer refuses.)
    if (tp.moves.size() > first || m.kind != MoveKind::Retract) m.axis = tilted;
    tp.moves.push_back(m);
  }
  tp.layerCount = 10;
  for (const std::string name : {"rotary4", "table5"}) {
    const MachineProfileResult machine = builtinMachine(name, {220, 220, 250}, 0.4);
    ASSERT_TRUE(machine.ok());
    const MachinePath path = planMachineMotion(tp, machine.machine);
    ASSERT_TRUE(path.ok()) << path.message;
    const WriteProgramResult w = writeProgram(path, infoFor(machine.machine));
    ASSERT_TRUE(w.ok()) << name << ": " << w.message;
    const ParsedProgram p = readProgram(w.text);
    ASSERT_TRUE(p.ok()) << p.message;
    const size_t marker = w.text.find("; omnislice:part 1 direction [");
    ASSERT_NE(marker, std::string::npos) << name;
    Eigen::Vector3d direction;
    ASSERT_EQ(std::sscanf(w.text.c_str() + marker, "; omnislice:part 1 direction [%lf,%lf,%lf]",
                          &direction.x(), &direction.y(), &direction.z()),
              3);
    EXPECT_LT((direction - tilted).norm(), 1e-6) << name;
    // The tilted part is printed with the tilted part-frame axis.
    size_t tiltedPrints = 0;
    for (const ProgramMove& m : p.moves) {
      if (m.part == 1 && m.filament > 0 && (m.to - m.from).norm() > 0) {
        EXPECT_LT((m.axis - tilted).norm(), 1e-4);
        ++tiltedPrints;
      }
    }
    EXPECT_GT(tiltedPrints, 10u);
  }
}

}  // namespace
}  // namespace omnislice
