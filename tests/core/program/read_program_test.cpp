// SPDX-License-Identifier: MIT
#include "program/read_program.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "program/write_gcode.h"
#include "test_toolpaths.h"

namespace omnislice {
namespace {

ProgramInfo testInfo() {
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.method = "planar";
  info.machine = cartesian3Profile({200, 180, 150}, 0.4);
  info.machine.nozzle.coneHalfAngleDegrees = 35;
  info.machine.nozzle.coneLength = 20;
  info.layerHeight = 0.2;
  info.lineWidth = 0.45;
  info.filamentDiameter = 2.85;
  info.placement << 0, -1, 0, 3, 1, 0, 0, -4, 0, 0, 1, 0.5, 0, 0, 0, 1;
  return info;
}

TEST(ReadProgram, RoundTripKeepsEveryMoveAndHeaderFact) {
  test::BoxPathOptions o;
  o.half = 4;
  o.height = 1.2;
  const Toolpath tp = test::boxToolpath(o);
  const ProgramInfo info = testInfo();
  const WriteProgramResult w = writeGcode(tp, info);
  ASSERT_TRUE(w.ok()) << w.message;
  const ParsedProgram p = readProgram(w.text);
  ASSERT_TRUE(p.ok()) << p.message;

  EXPECT_EQ(p.method, "planar");
  EXPECT_EQ(p.machine.kind, MachineKind::Cartesian3);
  EXPECT_EQ(p.machine.axisLimits, info.machine.axisLimits);
  EXPECT_EQ(p.machine.nozzle.coneHalfAngleDegrees, 35);
  EXPECT_EQ(p.machine.nozzle.coneLength, 20);
  EXPECT_TRUE(p.placement.isApprox(info.placement, 1e-12)) << p.placement;
  EXPECT_TRUE(p.absoluteExtrusion);
  EXPECT_EQ(p.filamentDiameter, 2.85);
  EXPECT_EQ(p.layerHeight, 0.2);
  EXPECT_EQ(p.lineWidth, 0.45);
  EXPECT_EQ(p.nozzleDiameter, 0.4);
  EXPECT_EQ(p.layerCount, 6);

  // Program moves: one travel to the start position, then one per tool-path move, then the end
  // code (retract, lift).
  size_t k = 1;
  ASSERT_GE(p.moves.size(), tp.moves.size() + 1);
  EXPECT_TRUE(p.moves[0].to.isApprox(tp.start, 1e-9));
  Eigen::Vector3d prev = tp.start;
  double filamentSum = 0;
  for (size_t i = 0; i < tp.moves.size(); ++i) {
    const Move& m = tp.moves[i];
    if ((m.position - prev).norm() == 0 && m.filament == 0) continue;  // nothing to replay
    ASSERT_LT(k, p.moves.size());
    const ProgramMove& pm = p.moves[k++];
    EXPECT_LE((pm.from - prev).cwiseAbs().maxCoeff(), 0.0005 + 1e-9) << "move " << i;
    EXPECT_LE((pm.to - m.position).cwiseAbs().maxCoeff(), 0.0005 + 1e-9) << "move " << i;
    EXPECT_NEAR(pm.filament, m.filament, 1.1e-5) << "move " << i;
    EXPECT_EQ(pm.axis, Eigen::Vector3d::UnitZ());
    EXPECT_EQ(pm.layer, m.layer) << "move " << i;
    // F reproduces the planned duration on the coordinates as written (rounded to 0.001 mm), so
    // it differs from the requested speed by that rounding only.
    EXPECT_NEAR(pm.feedMmPerMin, m.speed * 60, 0.01 * m.speed * 60) << "move " << i;
    if (m.kind == MoveKind::Print) {
      EXPECT_EQ(p.featureOf(pm), featureName(m.feature)) << "move " << i;
    }
    ASSERT_EQ(pm.axes.size(), 3u);
    EXPECT_EQ(pm.axes[0], pm.to.x());
    EXPECT_GT(pm.line, 10);
    filamentSum += pm.filament;
    prev = m.position;
  }
  // Rounding of absolute E never accumulates: the sum of increments equals the total.
  double exact = 0;
  for (const Move& m : tp.moves) exact += m.filament;
  EXPECT_NEAR(filamentSum, exact, 1e-5);
  // End code: a retract, then a lift straight up.
  ASSERT_EQ(p.moves.size(), k + 2);
  EXPECT_LT(p.moves[k].filament, 0);
  EXPECT_GT(p.moves[k + 1].to.z(), p.moves[k + 1].from.z());
}

TEST(ReadProgram, MalformedHeadersGiveParseErrorWithLine) {
  const std::string head = "; omnislice 0.1.0 planar 2026-11-21T12:00:00Z\n";
  ParsedProgram p = readProgram(head + "; omnislice:machine {\"kind\":\"cartesian3\",\n");
  EXPECT_EQ(p.status, Status::ParseError);
  EXPECT_NE(p.message.find("line 2"), std::string::npos) << p.message;

  p = readProgram(head + "; omnislice:placement [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0]\n");
  EXPECT_EQ(p.status, Status::ParseError);
  p = readProgram(head + "; omnislice:setting layer_height = abc\n");
  EXPECT_EQ(p.status, Status::ParseError);
  p = readProgram(head + "; omnislice:extrusion {\"mode\":\"sideways\"}\n");
  EXPECT_EQ(p.status, Status::ParseError);

  p = readProgram(head + "G21\nG90\nG1 X1 Y2 Z0.2 F1200\nG1 Xabc Y3\n");
  EXPECT_EQ(p.status, Status::ParseError);
  EXPECT_NE(p.message.find("line 5"), std::string::npos) << p.message;

  p = readProgram(head +
                  "; omnislice:machine {\"kind\":\"delta\",\"pivot\":[0,0,0],\"axis_limits\":"
                  "{\"B\":[-90,90]}}\n");
  EXPECT_EQ(p.status, Status::UnsupportedFormat);
  EXPECT_EQ(readProgram("").status, Status::EmptyInput);
  EXPECT_EQ(readProgram("G1 X1 Y1\nG2 X3 Y3 I1 J1\n").status, Status::UnsupportedFormat);
}

TEST(ReadProgram, PlainGcodeOfOtherSlicers) {
  // Cura-like: no omnislice header, relative E (M83), ;LAYER: and ;TYPE: markers.
  const std::string cura =
      ";FLAVOR:Marlin\n;Layer height: 0.15\nM83\nG28\nG92 E0\n;LAYER:0\n;TYPE:WALL-OUTER\n"
      "G0 F6000 X0 Y0 Z0.15\nG1 F1200 X10 Y0 E0.5\nG1 X10 Y10 E0.5\n;TYPE:FILL\nG1 X0 Y10 E0.4\n"
      "G1 E-0.8\n;LAYER:1\nG0 X0 Y0 Z0.3\nG1 E0.8\nG1 X5 Y0 E0.25 ; comment\n";
  const ParsedProgram p = readProgram(cura);
  ASSERT_TRUE(p.ok()) << p.message;
  EXPECT_EQ(p.machine.kind, MachineKind::Cartesian3);
  EXPECT_TRUE(p.machine.axisLimits.empty());
  EXPECT_FALSE(p.absoluteExtrusion);
  EXPECT_EQ(p.layerHeight, 0.15);
  EXPECT_EQ(p.lineWidth, 1.125 * 0.4);
  EXPECT_EQ(p.layerCount, 2);
  ASSERT_EQ(p.moves.size(), 8u);
  EXPECT_EQ(p.moves[1].filament, 0.5);
  EXPECT_EQ(p.featureOf(p.moves[1]), "wall-outer");
  EXPECT_EQ(p.moves[1].feedMmPerMin, 1200);
  EXPECT_EQ(p.featureOf(p.moves[3]), "infill");
  EXPECT_EQ(p.moves[4].filament, -0.8);
  EXPECT_EQ(p.moves[4].from, p.moves[4].to);
  EXPECT_EQ(p.moves[5].layer, 1);
  EXPECT_EQ(p.moves[7].to, Eigen::Vector3d(5, 0, 0.3));
  EXPECT_EQ(p.moves[7].line, 17);

  // Without a layer-height comment the height comes from the Z steps of extruding moves;
  // absolute E with G92 resets, and G91 relative positioning.
  const std::string plain =
      "G90\nM82\nG92 E0\nG1 X0 Y0 Z0.3\nG1 X10 E1\nG1 Z0.6\nG1 X0 E2\nG92 E0\nG1 Z0.9\n"
      "G1 X10 E1\nG91\nG1 X-2 Y1 E0.5\nG90\n";
  const ParsedProgram q = readProgram(plain);
  ASSERT_TRUE(q.ok()) << q.message;
  EXPECT_TRUE(q.absoluteExtrusion);
  EXPECT_NEAR(q.layerHeight, 0.3, 1e-12);
  ASSERT_EQ(q.moves.size(), 7u);
  EXPECT_EQ(q.moves[3].filament, 1.0);  // E1 -> E2
  EXPECT_EQ(q.moves[5].filament, 1.0);  // after G92 E0
  EXPECT_EQ(q.moves[6].to, Eigen::Vector3d(8, 1, 0.9));
  EXPECT_EQ(q.moves[6].filament, 0.5);
  EXPECT_EQ(q.layerCount, 0);
}

TEST(ReadProgram, NumbersAreReadAsStrtodReadsThem) {
  // Axis words in many spellings (signs, leading and trailing zeros, no integer or no fraction
  // part, exponents, up to 20 significant digits, hexadecimal): every value equals std::strtod's.
  std::mt19937 rng(77);
  auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
  auto number = [&]() {
    std::string t;
    if (pick(3) == 0) t += pick(2) ? "-" : "+";
    if (pick(40) == 0) return t + (pick(2) ? "0x1A.8p-3" : "0X7f");
    const int lead = pick(5) == 0 ? pick(4) : 0;
    t += std::string(size_t(lead), '0');
    const int intDigits = pick(4) == 0 ? 0 : 1 + pick(pick(5) == 0 ? 20 : 4);
    for (int i = 0; i < intDigits; ++i) t += char('0' + pick(10));
    const int fracDigits = pick(5) == 0 ? 0 : pick(pick(5) == 0 ? 22 : 7);
    if (fracDigits > 0 || intDigits == 0 || pick(10) == 0) t += '.';
    for (int i = 0; i < fracDigits; ++i) t += char('0' + pick(10));
    if (intDigits == 0 && fracDigits == 0) t += '5';
    if (pick(4) == 0) {
      t += pick(2) ? 'e' : 'E';
      if (pick(2)) t += pick(2) ? "-" : "+";
      t += std::to_string(pick(pick(4) == 0 ? 40 : 25));
    }
    return t;
  };
  std::string text = "G21\n";
  std::vector<Eigen::Vector3d> expected;
  Eigen::Vector3d at(0, 0, 0);
  for (int line = 0; line < 20000; ++line) {
    const std::string x = number(), y = number(), z = number();
    text += "G1 X" + x + " Y " + y + " Z" + z + (pick(3) == 0 ? " ; note\n" : "\n");
    const Eigen::Vector3d v(std::strtod(x.c_str(), nullptr), std::strtod(y.c_str(), nullptr),
                            std::strtod(z.c_str(), nullptr));
    if (!v.allFinite()) {
      text.erase(text.rfind("G1 X"));
      continue;
    }
    if (v != at) expected.push_back(v);
    at = v;
  }
  const ParsedProgram p = readProgram(text);
  ASSERT_TRUE(p.ok()) << p.message;
  ASSERT_EQ(p.moves.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(p.moves[i].to[k], expected[i][k]) << "move " << i << " axis " << k;
      ASSERT_EQ(std::signbit(p.moves[i].to[k]), std::signbit(expected[i][k]));
    }
  }
}

TEST(ReadProgram, GarbageAndMutatedProgramsNeverCrash) {
  // Bad input gives a status, never a crash or a hang: random bytes, and a real program with
  // random characters overwritten / lines cut short.
  test::BoxPathOptions o;
  o.half = 2;
  o.height = 0.6;
  const WriteProgramResult w = writeGcode(test::boxToolpath(o), testInfo());
  ASSERT_TRUE(w.ok());
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> byte(0, 255);
  int errors = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string text = w.text;
    if (trial % 3 == 0) {
      text.assign(200 + trial, ' ');
      for (char& c : text) c = char(byte(rng));
    } else {
      std::uniform_int_distribution<size_t> at(0, text.size() - 1);
      for (int k = 0; k < 1 + trial % 7; ++k) text[at(rng)] = "GXE;{[0.-e9\n #"[byte(rng) % 15];
      if (trial % 3 == 2) text.resize(at(rng));
    }
    const ParsedProgram p = readProgram(text);
    if (!p.ok()) {
      ++errors;
      EXPECT_FALSE(p.message.empty());
      EXPECT_TRUE(p.moves.empty());
    }
    for (const ProgramMove& m : p.moves) {
      EXPECT_TRUE(m.from.allFinite() && m.to.allFinite() && std::isfinite(m.filament));
    }
  }
  EXPECT_GT(errors, 0);
}

}  // namespace
}  // namespace omnislice
