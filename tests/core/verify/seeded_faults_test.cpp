// SPDX-License-Identifier: MIT
// Verification by simulation of multi-axis programs: a correct program (a solid box mapped through
// the machine, written, read back) passes; one seeded fault per test makes exactly the measure
// that should catch it fail, on more than one machine kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "../program/machine_paths.h"
#include "../program/test_toolpaths.h"
#include "../test_meshes.h"
#include "../test_support.h"
#include "program/read_program.h"
#include "program/write_gcode.h"
#include "verify/verify_program.h"

namespace omnislice {
namespace {

const Mesh& box10() {
  static const Mesh m = test::makeBox(-5, -5, 0, 5, 5, 10);
  return m;
}

// Machine values for part-frame point q on `layer`; `prev` are the previous move's values.
using ValuesFn = std::function<bool(const Eigen::Vector3d& q, int layer, const MachineValues& prev,
                                    MachineValues& out)>;

// The tool-path mapped move by move (tips and axes from the forward map of the chosen values).
MachinePath mapToolpath(const Toolpath& tp, const MachineProfile& machine, const ValuesFn& values) {
  MachineValues start{};
  EXPECT_TRUE(values(tp.start, tp.moves.empty() ? 0 : tp.moves.front().layer, start, start));
  test::MachinePathBuilder b(machine, start);
  for (const Move& m : tp.moves) {
    MachineValues v{};
    if (!values(m.position, m.layer, b.current(), v)) {
      ADD_FAILURE() << "no machine values for a move";
      return b.path;
    }
    b.layer = m.layer;
    if (m.kind == MoveKind::Retract || m.kind == MoveKind::Unretract) {
      b.push(b.current(), m.kind, m.filament, std::abs(m.filament) / 35, Feature::None);
    } else {
      b.go(v, m.kind, m.filament, m.speed > 0 ? m.speed : 40, m.feature);
    }
  }
  return b.path;
}

VerifyReport verifyPath(const MachinePath& path) {
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.machine = path.machine;
  info.layerHeight = 0.2;
  info.lineWidth = 0.45;
  const WriteProgramResult w = writeProgram(path, info);
  EXPECT_TRUE(w.ok()) << w.message;
  const ParsedProgram p = readProgram(w.text);
  EXPECT_TRUE(p.ok()) << p.message;
  return verifyProgram(p, box10());
}

void expectPasses(const VerifyReport& r) {
  ASSERT_TRUE(r.ok()) << r.message;
  std::printf("%s\n", verifyReportJson(r).c_str());
  EXPECT_GE(r.inside, 0.99);
  EXPECT_GE(r.coverage, 0.95);
  EXPECT_GE(r.supported, 0.99);
  EXPECT_EQ(r.collisions, 0u);
  EXPECT_EQ(r.limitViolations, 0u);
}

// ---- table5: pivot off the part, C turned by 7 degrees per layer (axis stays +Z) ----

MachineProfile table5() {
  MachineProfile m;
  m.kind = MachineKind::Table5;
  m.pivot = {20, 0, 0};
  m.axisLimits = {{"X", {-150, 150}}, {"Y", {-150, 150}}, {"Z", {0, 200}},
                  {"B", {-90, 90}},   {"C", {-360, 360}}};
  return m;
}

// Fault hooks: per layer, the (B, C) used to compute the values and the (B, C) written.
struct TableFault {
  std::function<double(int)> tiltB = [](int) { return 0.0; };      // B used for the mapping
  std::function<double(int)> writtenCOffset = [](int) { return 0.0; };  // added to C as written
  std::function<double(int)> cOffset = [](int) { return 0.0; };    // added to C and mapped (alias)
};

MachinePath table5Box(const test::BoxPathOptions& o, const TableFault& fault = {}) {
  const MachineProfile m = table5();
  return mapToolpath(test::boxToolpath(o), m,
                     [&](const Eigen::Vector3d& q, int layer, const MachineValues&, MachineValues& out) {
                       const double c = 7.0 * layer + fault.cOffset(layer);
                       out = test::gcodeValues(m, q, fault.tiltB(layer), c);
                       out[4] += fault.writtenCOffset(layer);
                       return true;
                     });
}

TEST(SeededFaults, Table5CorrectBoxPasses) {
  const MachinePath path = table5Box({});
  expectPasses(verifyPath(path));
}

TEST(SeededFaults, Table5MoveThroughTheWrongPlaceDropsInside) {
  // Layers 20-29 are written with C 40 degrees off the values the mapping assumed: the machine
  // puts those beads 40 degrees around the pivot, outside the part.
  TableFault f;
  f.writtenCOffset = [](int l) { return l >= 20 && l < 30 ? 40.0 : 0.0; };
  const VerifyReport r = verifyPath(table5Box({}, f));
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(r.inside, 0.9);
  EXPECT_GT(r.inside, 0.7);
  EXPECT_EQ(r.limitViolations, 0u);
}

TEST(SeededFaults, Table5FloatingBeadIsUnsupported) {
  test::BoxPathOptions good, floating;
  good.keepLayer = [](int l) { return l < 5; };
  floating.keepLayer = [](int l) { return l >= 25 && l < 30; };  // starts 5 mm above the bed
  const VerifyReport rg = verifyPath(table5Box(good));
  const VerifyReport rf = verifyPath(table5Box(floating));
  ASSERT_TRUE(rg.ok() && rf.ok());
  EXPECT_GE(rg.supported, 0.99);
  EXPECT_LT(rf.supported, 0.85);
  EXPECT_EQ(rf.collisions, 0u);
}

TEST(SeededFaults, Table5TiltedNozzleHitsEarlierMaterial) {
  // The top five layers printed with B = 60 degrees: the part-frame nozzle axis leans 60 degrees,
  // so the cone (40 degrees half-angle) sweeps over the beads already laid on the same layer.
  TableFault f;
  f.tiltB = [](int l) { return l >= 45 ? 60.0 : 0.0; };
  const VerifyReport r = verifyPath(table5Box({}, f));
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_GT(r.collisions, 100u);
  EXPECT_GE(r.inside, 0.99);  // the tips are where they should be
  EXPECT_EQ(r.limitViolations, 0u);
  // A 30 degree lean keeps the cone clear of a planar layer (90 - 30 > 40 degrees).
  f.tiltB = [](int l) { return l >= 45 ? 30.0 : 0.0; };
  EXPECT_EQ(verifyPath(table5Box({}, f)).collisions, 0u);
}

// Samples with an earlier sample strictly inside their nozzle cone, by the definition of
// PROGRAM-FORMAT.md checked pair by pair (independent of the verifier's cell hierarchy).
size_t bruteForceCollisions(const ParsedProgram& p, double h, double halfAngleDeg, double length) {
  std::vector<Eigen::Vector3d> tips, axes;
  for (const ProgramMove& m : p.moves) {
    const double len = (m.to - m.from).norm();
    if (!(m.filament > 0) || !(len > 1e-9)) continue;
    for (int k = 0; k == 0 || k * 0.5 < len; ++k) {
      tips.push_back(m.from + (k * 0.5 / len) * (m.to - m.from));
      axes.push_back(m.axis.normalized());
    }
  }
  const double tol = 0.001, tanT = std::tan(halfAngleDeg * M_PI / 180);
  size_t n = 0;
  for (size_t i = 0; i < tips.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const Eigen::Vector3d d = tips[j] - tips[i];
      const double a = d.dot(axes[i]);
      const double lat = std::sqrt(std::max(0.0, d.squaredNorm() - a * a));
      if (a > h + tol && d.norm() < length - tol && lat < a * tanT - tol) {
        ++n;
        break;
      }
    }
  }
  return n;
}

TEST(SeededFaults, CollisionCountEqualsThePairByPairCount) {
  // A small box whose layers lean by -20, 0 or 20 degrees, the top ones by 60 (the cone sweeps
  // over the beads of the same layer), and the same box printed from the top layer down.
  test::BoxPathOptions o;
  o.half = 3;
  o.height = 4;
  TableFault f;
  f.tiltB = [](int l) { return l >= 15 ? 60.0 : 20.0 * (l % 3) - 20.0; };
  const MachinePath leaning = table5Box(o, f);
  Toolpath downward = test::boxToolpath(o);
  std::stable_sort(downward.moves.begin(), downward.moves.end(),
                   [](const Move& a, const Move& b) { return a.layer > b.layer; });
  const MachinePath topDown = mapToolpath(
      downward, table5(), [&](const Eigen::Vector3d& q, int layer, const MachineValues&, MachineValues& out) {
        out = test::gcodeValues(table5(), q, 15.0 * (layer % 2), 7.0 * layer);
        return true;
      });
  for (const MachinePath* path : {&leaning, &topDown}) {
    ProgramInfo info;
    info.isoDate = "2026-11-21T12:00:00Z";
    info.machine = path->machine;
    info.layerHeight = 0.2;
    info.lineWidth = 0.45;
    const WriteProgramResult w = writeProgram(*path, info);
    ASSERT_TRUE(w.ok()) << w.message;
    const ParsedProgram p = readProgram(w.text);
    ASSERT_TRUE(p.ok()) << p.message;
    const VerifyReport r = verifyProgram(p, box10());
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_GT(r.collisions, 100u);
    EXPECT_EQ(r.collisions, bruteForceCollisions(p, 0.2, p.machine.nozzle.coneHalfAngleDegrees,
                                                 p.machine.nozzle.coneLength));
    ASSERT_EQ(r.collisionExamples.size(), 10u);
    for (const CollisionExample& e : r.collisionExamples) {
      const Eigen::Vector3d tip(e.tip[0], e.tip[1], e.tip[2]), u(e.axis[0], e.axis[1], e.axis[2]),
          q(e.earlier[0], e.earlier[1], e.earlier[2]);
      const Eigen::Vector3d d = q - tip;
      EXPECT_GT(d.dot(u), 0.2);
      EXPECT_LT(d.norm(), p.machine.nozzle.coneLength);
    }
  }
}

TEST(SeededFaults, CoverageOfLeaningBeadsEqualsThePointBySegmentCount) {
  // A 3 x 3 x 1.2 mm box whose layers lean by -20, 0 and 20 degrees: every interior point of a
  // 0.043 mm grid against every extruding segment, with the bead's reach in the segment's frame.
  test::BoxPathOptions o;
  o.half = 1.5;
  o.height = 1.2;
  o.keepLayer = [](int l) { return l % 2 == 0; };  // beads apart, each point reached by few
  TableFault f;
  f.tiltB = [](int l) { return 20.0 * (l % 3) - 20.0; };
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.machine = table5();
  info.layerHeight = 0.2;
  info.lineWidth = 0.45;
  const WriteProgramResult w = writeProgram(table5Box(o, f), info);
  ASSERT_TRUE(w.ok()) << w.message;
  const ParsedProgram p = readProgram(w.text);
  ASSERT_TRUE(p.ok()) << p.message;
  VerifyOptions fine;
  fine.gridSpacing = 0.043;  // off the layer heights: points fall anywhere in the beads
  const VerifyReport r = verifyProgram(p, test::makeBox(-1.5, -1.5, 0, 1.5, 1.5, 1.2), fine);
  ASSERT_TRUE(r.ok()) << r.message;
  const double g = 0.043, rax = 0.75 * 0.2, rlat = 0.75 * 0.45;
  size_t interior = 0, covered = 0;
  for (int i = -40; i <= 40; ++i)
    for (int j = -40; j <= 40; ++j)
      for (int k = 0; k <= 30; ++k) {
        const Eigen::Vector3d q(i * g, j * g, k * g);
        const double d = std::min({q.x() + 1.5, 1.5 - q.x(), q.y() + 1.5, 1.5 - q.y(), q.z(), 1.2 - q.z()});
        if (d < 0.225) continue;
        ++interior;
        for (const ProgramMove& m : p.moves) {
          const Eigen::Vector3d ab = m.to - m.from;
          if (!(m.filament > 0) || !(ab.norm() > 1e-9)) continue;
          const Eigen::Vector3d u = m.axis.normalized();
          const double t = std::clamp((q - m.from).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
          const Eigen::Vector3d dd = q - (m.from + t * ab);
          const double ax = dd.dot(u), lat2 = std::max(0.0, dd.squaredNorm() - ax * ax);
          if ((ax * ax) / (rax * rax) + lat2 / (rlat * rlat) <= 1.0) {
            ++covered;
            break;
          }
        }
      }
  EXPECT_EQ(r.gridPoints, interior);
  EXPECT_EQ(r.coverage, double(covered) / double(interior));
  EXPECT_GT(r.coverage, 0.2);
}

TEST(SeededFaults, Table5RotaryAxisOverItsLimit) {
  // Layers 10-11 with C + 720: the same orientation, but C beyond its +-360 limit.
  TableFault f;
  f.cOffset = [](int l) { return l == 10 || l == 11 ? 720.0 : 0.0; };
  const VerifyReport r = verifyPath(table5Box({}, f));
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_GT(r.limitViolations, 20u);
  EXPECT_GE(r.inside, 0.99);
  EXPECT_EQ(r.collisions, 0u);
}

// ---- rotary4: pivot 30 mm above the bed ----

MachineProfile rotary4() {
  MachineProfile m;
  m.kind = MachineKind::Rotary4;
  m.pivot = {0, 0, 30};
  m.axisLimits = {{"X", {-150, 150}}, {"Y", {-150, 150}}, {"Z", {0, 200}}, {"A", {-60, 60}}};
  return m;
}

MachinePath rotary4Box(const test::BoxPathOptions& o, std::function<double(int)> mappedA,
                       std::function<double(int)> writtenA) {
  const MachineProfile m = rotary4();
  return mapToolpath(test::boxToolpath(o), m,
                     [&](const Eigen::Vector3d& q, int layer, const MachineValues&, MachineValues& out) {
                       out = test::gcodeValues(m, q, mappedA(layer));
                       out[3] += writtenA(layer);
                       return true;
                     });
}

TEST(SeededFaults, Rotary4CorrectAndFaultyPrograms) {
  const auto zero = [](int) { return 0.0; };
  expectPasses(verifyPath(rotary4Box({}, zero, zero)));
  // Inside: layers 30-39 written with A off by 20 degrees (turned about the pivot 30 mm up).
  const VerifyReport inside =
      verifyPath(rotary4Box({}, zero, [](int l) { return l >= 30 && l < 40 ? 20.0 : 0.0; }));
  ASSERT_TRUE(inside.ok());
  EXPECT_LT(inside.inside, 0.9);
  // Floating: only layers 25-29.
  test::BoxPathOptions floating;
  floating.keepLayer = [](int l) { return l >= 25 && l < 30; };
  const VerifyReport fl = verifyPath(rotary4Box(floating, zero, zero));
  ASSERT_TRUE(fl.ok());
  EXPECT_LT(fl.supported, 0.85);
  // Collision: top layers printed at A = 55 (the axis leans 55 degrees about X).
  const VerifyReport col = verifyPath(rotary4Box({}, [](int l) { return l >= 45 ? 55.0 : 0.0; }, zero));
  ASSERT_TRUE(col.ok());
  EXPECT_GT(col.collisions, 100u);
  EXPECT_GE(col.inside, 0.99);
  // Limits: layer 5 mapped (consistently) at A = 61 degrees, beyond the +-60 limit.
  const VerifyReport lim = verifyPath(rotary4Box({}, [](int l) { return l == 5 ? 61.0 : 0.0; }, zero));
  ASSERT_TRUE(lim.ok());
  EXPECT_GT(lim.limitViolations, 10u);
}

}  // namespace
}  // namespace omnislice

namespace omnislice {
namespace {

// ---- robot6 (UR5): the platform held flat (or tilted) under the fixed nozzle ----

struct RobotFault {
  std::function<double(int)> tiltDegrees = [](int) { return 0.0; };   // platform tilt about y
  std::function<double(int)> q1Offset = [](int) { return 0.0; };      // added to q1 as written
  std::function<bool(int)> wrapQ6 = [](int) { return false; };         // q6 +- 2 pi (same pose)
};

MachinePath robotBox(const test::BoxPathOptions& o, const RobotFault& fault = {}) {
  const MachineProfile m = test::ur5TestMachine();
  bool first = true;
  MachineValues solved{};
  return mapToolpath(
      test::boxToolpath(o), m,
      [&](const Eigen::Vector3d& q, int layer, const MachineValues&, MachineValues& out) {
        const Eigen::Matrix3d rot = test::rotDeg(1, fault.tiltDegrees(layer)).transpose();
        bool ok = first ? test::robotStart(m, q, rot, solved)
                        : test::robotValues(m, q, rot, solved, solved);
        first = false;
        out = solved;
        out[0] += fault.q1Offset(layer);
        if (fault.wrapQ6(layer)) out[5] += out[5] >= 0 ? 2 * M_PI : -2 * M_PI;
        return ok;
      });
}

TEST(SeededFaults, Robot6CorrectBoxPasses) {
  const MachinePath path = robotBox({});
  ASSERT_GT(path.moves.size(), 1000u);
  expectPasses(verifyPath(path));
}

TEST(SeededFaults, Robot6Faults) {
  RobotFault inside;
  inside.q1Offset = [](int l) { return l >= 20 && l < 30 ? 0.03 : 0.0; };
  const VerifyReport ri = verifyPath(robotBox({}, inside));
  ASSERT_TRUE(ri.ok()) << ri.message;
  EXPECT_LT(ri.inside, 0.9);

  test::BoxPathOptions floating;
  floating.keepLayer = [](int l) { return l >= 25 && l < 30; };
  const VerifyReport rf = verifyPath(robotBox(floating));
  ASSERT_TRUE(rf.ok()) << rf.message;
  EXPECT_LT(rf.supported, 0.85);

  RobotFault tilt;
  tilt.tiltDegrees = [](int l) { return l >= 45 ? 60.0 : 0.0; };
  const VerifyReport rc = verifyPath(robotBox({}, tilt));
  ASSERT_TRUE(rc.ok()) << rc.message;
  EXPECT_GT(rc.collisions, 100u);
  EXPECT_GE(rc.inside, 0.99);

  RobotFault wrap;
  wrap.wrapQ6 = [](int l) { return l == 10 || l == 11; };
  const VerifyReport rl = verifyPath(robotBox({}, wrap));
  ASSERT_TRUE(rl.ok()) << rl.message;
  EXPECT_GT(rl.limitViolations, 20u);
  EXPECT_GE(rl.inside, 0.99);
  EXPECT_EQ(rl.collisions, 0u);
}

}  // namespace
}  // namespace omnislice
