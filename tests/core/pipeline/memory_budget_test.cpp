// SPDX-License-Identifier: MIT
// Issue 29 item 3: the memory budget (setting memory_mb, common/memory_budget.h). A structure
// estimated larger than the budget is refused with out_of_memory naming the figure and the setting
// before it is allocated; the figures it names are consistent (a budget of the named figure passes
// that check) and near what the job really uses (the process's peak resident memory).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>

#include "../test_meshes.h"
#include "common/memory_budget.h"
#include "pipeline/method.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"
#include "program/read_program.h"
#include "verify/verify_program.h"

namespace omnislice {
namespace {

// "... needs about N MB, more than the memory budget (memory_mb = B MB); ...": N, or -1.
double neededMb(const std::string& message) {
  static const std::regex re("needs about ([0-9]+) MB, more than the memory budget \\(memory_mb = ([0-9]+) MB\\)");
  std::smatch m;
  if (!std::regex_search(message, m, re)) return -1;
  return std::stod(m[1].str());
}

TEST(MemoryBudget, CheckNamesTheFigureTheBudgetAndTheLever) {
  EXPECT_TRUE(checkMemoryBudget(100.0 * 1024 * 1024, 100, "x", "y").ok());
  const Outcome o = checkMemoryBudget(100.5 * 1024 * 1024, 100, "the voxel grid", "raise voxel.width_mm");
  EXPECT_EQ(o.status, Status::OutOfMemory);
  EXPECT_EQ(o.message, "the voxel grid needs about 101 MB, more than the memory budget (memory_mb = 100 MB); "
                       "raise voxel.width_mm");
  EXPECT_EQ(neededMb(o.message), 101);
  EXPECT_TRUE(checkMemoryBudget(1e30, 0, "x", "y").ok());  // no budget
  EXPECT_EQ(checkMemoryBudget(std::nan(""), 100, "x", "y").status, Status::OutOfMemory);
  EXPECT_EQ(allocationFailed("slicing").status, Status::OutOfMemory);
}

TEST(MemoryBudget, SettingIsRangeChecked) {
  Settings s;
  EXPECT_EQ(s.memoryMb, kDefaultMemoryBudgetMb);
  EXPECT_TRUE(setSetting(s, "memory_mb", "512").ok());
  EXPECT_EQ(s.memoryMb, 512);
  EXPECT_EQ(setSetting(s, "memory_mb", "0").status, Status::InvalidOption);
  EXPECT_EQ(setSetting(s, "memory_mb", "nan").status, Status::InvalidOption);
}

// Every multi-axis method from a 16 MB budget: each refusal names a figure above the budget it was
// refused at, and a budget of that figure gets past that structure, until the slice is made (within
// a few steps: one per structure). Catches a figure that is not what the check compares.
TEST(MemoryBudget, RaisingTheBudgetToTheNamedFigureGetsPastEachStructure) {
  const auto bytes = test::binaryStl(test::onPlatform(test::makeUvSphere(12, 48, 24)));
  for (Method method : {Method::Voxel, Method::Geodesic, Method::Planar}) {
    Settings s = test::coarseCurvedSettings(method);
    if (method == Method::Planar) s.machine = "cartesian3";
    s.memoryMb = 16;
    int refusals = 0;
    SliceOutput out;
    for (int step = 0; step < 6; ++step) {
      out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
      if (out.status != Status::OutOfMemory) break;
      ++refusals;
      const double need = neededMb(out.message);
      ASSERT_GT(need, s.memoryMb) << out.message;
      EXPECT_NE(out.message.find("memory_mb"), std::string::npos) << out.message;
      s.memoryMb = need;
    }
    ASSERT_TRUE(out.ok()) << methodName(method) << ": " << out.message;
    if (method != Method::Planar) {
      EXPECT_GE(refusals, 1) << methodName(method);
    }
  }
}

// The geodesic method names its lever; an absurd tet target is refused before meshing (at once,
// not after minutes of meshing).
TEST(MemoryBudget, GeodesicTetTargetBeyondTheBudgetIsRefusedBeforeMeshing) {
  const auto bytes = test::binaryStl(test::onPlatform(test::makeUvSphere(9, 48, 24)));
  Settings s = test::coarseCurvedSettings(Method::Geodesic);
  s.geodesic.targetTets = 5e6;  // about 5.7 GB
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  EXPECT_EQ(out.status, Status::OutOfMemory) << out.message;
  EXPECT_NE(out.message.find("geodesic.target_tets"), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("5000000 tets"), std::string::npos) << out.message;
}

// Verify's samples and coverage grid: refused over the budget, the same program verifies under it.
TEST(MemoryBudget, VerifyChecksItsSamplesAgainstTheBudget) {
  const Mesh sphere = test::onPlatform(test::makeUvSphere(9, 48, 24));
  const auto bytes = test::binaryStl(sphere);
  Settings s;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const ParsedProgram program = readProgram(out.program);
  ASSERT_TRUE(program.ok()) << program.message;
  VerifyOptions o;
  o.memoryBudgetMb = 1;
  const VerifyReport refused = verifyProgram(program, sphere, o);
  EXPECT_EQ(refused.status, Status::OutOfMemory) << refused.message;
  EXPECT_NE(refused.message.find("verifying the program"), std::string::npos) << refused.message;
  const double need = neededMb(refused.message);
  ASSERT_GT(need, 1) << refused.message;
  o.memoryBudgetMb = need;
  EXPECT_TRUE(verifyProgram(program, sphere, o).ok());
  // Before that, the parsed program is estimated from its text (runVerify, the CLI and wasm entry).
  ASSERT_GT(out.program.size(), 100000u);
  const VerifyOutput text = runVerify(out.program, bytes.data(), bytes.size(), "sphere.stl", {}, 1);
  EXPECT_EQ(text.status, Status::OutOfMemory) << text.message;
  EXPECT_EQ(text.message.rfind("reading the program (", 0), 0u) << text.message;
  EXPECT_TRUE(runVerify(out.program, bytes.data(), bytes.size(), "sphere.stl").ok());
}

// The parsed program's estimate (kProgramTextBytes per byte of text) bounds what the parse holds:
// its moves (pieces of interpolated rotary and joint moves included) and the deque's blocks, on
// programs of every kind of writer, with the most pieces per byte where axes turn (voxel on
// table5). A quarter of the bound is kept as margin; and the bound is not loose by more than 4x
// on the densest of them, so a wrong per-move size or a parse that doubles its moves fails here.
TEST(MemoryBudget, ProgramTextEstimateBoundsTheParsedMoves) {
  const auto bytes = test::binaryStl(test::onPlatform(test::makeUvSphere(8, 48, 24)));
  struct Case {
    Method method;
    const char* machine;
    const char* robotFormat;
  };
  double densest = 0;
  for (const Case c : {Case{Method::Planar, "cartesian3", ""}, Case{Method::Voxel, "table5", ""},
                       Case{Method::Voxel, "robot6-ur5", "csv"}, Case{Method::Multidir, "rotary4", ""},
                       Case{Method::Voxel, "robot6-irb1200", "rapid"}}) {
    Settings s = c.method == Method::Planar ? Settings() : test::coarseCurvedSettings(c.method);
    s.machine = c.machine;
    if (*c.robotFormat) ASSERT_TRUE(setSetting(s, "robot_format", c.robotFormat).ok());
    s.verify = VerifyMode::Off;
    const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
    ASSERT_TRUE(out.ok()) << c.machine << ": " << out.message;
    const ParsedProgram p = readProgram(out.program);
    ASSERT_TRUE(p.ok()) << c.machine << ": " << p.message;
    const double held = double(p.moves.size()) * sizeof(ProgramMove);
    const double perByte = held / double(out.program.size());
    densest = std::max(densest, perByte);
    RecordProperty(std::string(c.machine) + "_bytes_per_text_byte", std::to_string(perByte));
    EXPECT_LE(perByte, 0.75 * memory_cost::kProgramTextBytes)
        << c.machine << ": " << p.moves.size() << " moves from " << out.program.size() << " bytes";
  }
  EXPECT_GE(densest, memory_cost::kProgramTextBytes / 4) << "the estimate is far above every program";
}

// Peak resident memory of this process, MB (Linux); -1 when unknown.
double peakResidentMb() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return -1;
}

#if defined(__SANITIZE_ADDRESS__)
#define OMNISLICE_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OMNISLICE_UNDER_ASAN 1
#endif
#endif

// The voxel method's estimate against what the job really holds: the process's peak resident
// memory while slicing (after a refusal that allocated little). The estimate is a guard, rounded
// up: within [0.5, 3] x the measured growth.
TEST(MemoryBudget, VoxelEstimateIsNearTheMeasuredPeak) {
#ifdef OMNISLICE_UNDER_ASAN
  GTEST_SKIP() << "AddressSanitizer's shadow memory and quarantine inflate resident memory";
#endif
  const auto bytes = test::binaryStl(test::onPlatform(test::makeUvSphere(12, 64, 32)));
  Settings s = test::coarseCurvedSettings(Method::Voxel);
  s.voxel.widthMm = 0.3;  // about 250k voxels
  s.verify = VerifyMode::Off;
  s.memoryMb = 16;
  const SliceOutput refused = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_EQ(refused.status, Status::OutOfMemory) << refused.message;
  ASSERT_NE(refused.message.find("the voxel method"), std::string::npos) << refused.message;
  const double estimate = neededMb(refused.message);
  const double before = peakResidentMb();
  if (before < 0) GTEST_SKIP() << "no /proc/self/status";
  s.memoryMb = kDefaultMemoryBudgetMb;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const double grown = peakResidentMb() - before;
  RecordProperty("estimate_mb", std::to_string(estimate));
  RecordProperty("measured_mb", std::to_string(grown));
  EXPECT_GE(estimate, 0.5 * grown) << "estimate " << estimate << " MB, measured " << grown << " MB";
  EXPECT_LE(estimate, 3.0 * grown) << "estimate " << estimate << " MB, measured " << grown << " MB";
}

}  // namespace
}  // namespace omnislice
