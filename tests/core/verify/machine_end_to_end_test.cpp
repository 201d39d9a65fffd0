// SPDX-License-Identifier: MIT
// A planar tool-path (d = +Z in the part frame) planned on every built-in machine
// (planMachineMotion), written in every dialect / robot format, read back and verified: every
// kind passes, and the program's time is the planner's.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "../program/test_toolpaths.h"
#include "../test_meshes.h"
#include "../test_support.h"
#include "motion/plan_motion.h"
#include "program/read_program.h"
#include "program/write_gcode.h"
#include "verify/verify_program.h"

namespace omnislice {
namespace {

TEST(VerifyProgram, PlannedBoxPassesOnEveryMachine) {
  test::BoxPathOptions o;
  o.height = 4;
  // Infill lines 0.41 mm apart: a sample midway between two lines of the layer below is then
  // 0.28 mm from them, within the checker's reach 1.5 h = 0.3 mm. (At the default 0.45 mm width
  // the lines are 0.456 mm apart and a midway sample is 0.303 mm away: whether a sample falls
  // there depends on where a planner splits a move, e.g. the KR 6's spherical wrist splits the
  // infill lines at their middle, and the figure changed with the arm.)
  o.w = 0.41;
  const Toolpath tp = test::boxToolpath(o);
  const Mesh box = test::makeBox(-5, -5, 0, 5, 5, 4);
  for (const std::string& name : builtinMachineNames()) {
    const MachineProfileResult machine = builtinMachine(name, {220, 220, 250}, 0.4);
    ASSERT_TRUE(machine.ok()) << machine.message;
    const auto t0 = std::chrono::steady_clock::now();
    const MachinePath path = planMachineMotion(tp, machine.machine);
    ASSERT_TRUE(path.ok()) << name << ": " << path.message;
    const auto t1 = std::chrono::steady_clock::now();
    const bool robot = machine.machine.kind == MachineKind::Robot6;
    const int variants = robot ? 4 : 3;  // csv, urscript, rapid, krl; marlin, reprap, klipper
    for (int v = 0; v < variants; ++v) {
      ProgramInfo info;
      info.isoDate = "2026-11-21T12:00:00Z";
      info.machine = machine.machine;
      info.layerHeight = 0.2;
      info.lineWidth = 0.45;
      info.dialect = GcodeDialect(v);
      info.robotFormat = RobotFormat(v);
      const WriteProgramResult w = writeProgram(path, info);
      ASSERT_TRUE(w.ok()) << name << ": " << w.message;
      if (robot && info.robotFormat == RobotFormat::Krl) {
        // Whole percentages of the joint speeds: never faster than planned.
        EXPECT_GE(w.estimatedTimeS, path.stats.estimatedTimeS - 1e-9);
      } else {
        EXPECT_NEAR(w.estimatedTimeS, path.stats.estimatedTimeS, 1e-9);
      }
      const ParsedProgram p = readProgram(w.text);
      ASSERT_TRUE(p.ok()) << name << ": " << p.message;
      const VerifyReport r = verifyProgram(p, box);
      ASSERT_TRUE(r.ok()) << r.message;
      const auto t2 = std::chrono::steady_clock::now();
      std::printf("%s %s: %zu machine moves, plan %.2f s, %zu pieces, %s\n", name.c_str(),
                  robot ? robotFormatName(info.robotFormat) : gcodeDialectName(info.dialect),
                  path.moves.size(), std::chrono::duration<double>(t1 - t0).count(),
                  p.moves.size(), verifyReportJson(r).c_str());
      (void)t2;
      EXPECT_GE(r.inside, 0.99) << name;
      // head4 prints these flat layers with its nozzle leaning 45 degrees, and the format's bead
      // reach is an ellipsoid along the nozzle axis: leaning it leaves up to 6 % of the solid box's
      // grid points outside every reach (0.938 at 0.45 mm lines, 0.991 at these 0.41 mm; 1.0
      // upright).
      EXPECT_GE(r.coverage, machine.machine.kind == MachineKind::Head4 ? 0.93 : 0.95) << name;
      EXPECT_GE(r.supported, 0.99) << name;

      EXPECT_EQ(r.collisions, 0u) << name;
      EXPECT_EQ(r.limitViolations, 0u) << name;
      EXPECT_EQ(r.layers, 20) << name;
    }
  }
}

}  // namespace
}  // namespace omnislice
