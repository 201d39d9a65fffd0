// SPDX-License-Identifier: MIT
// End to end: readMesh + prepareMesh + placeMesh + sliceMesh + planLayers + writeGcode +
// readProgram + verifyProgram on real models at 100 % infill.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <set>

#include "../test_support.h"
#include "mesh/place_mesh.h"
#include "pipeline/settings.h"
#include "program/read_program.h"
#include "program/write_gcode.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "verify/verify_program.h"

namespace omnislice {
namespace {

struct EndToEnd {
  VerifyReport report;
  double verifySeconds = 0;
  size_t moves = 0;
};

EndToEnd sliceAndVerify(const std::string& file, UpAxis up, double fitMm, double infill) {
  EndToEnd out;
  const Mesh prepared = test::loadModel(file);
  Settings settings;
  settings.placement.up = up;
  settings.placement.fitMm = fitMm;
  settings.infillPercent = infill;
  const PlaceMeshResult placed = placeMesh(prepared, settings.placement);
  EXPECT_TRUE(placed.ok()) << placed.message;
  SliceOptions so;
  so.layerHeight = settings.layerHeight;
  const SliceResult slices = sliceMesh(placed.mesh, so);
  EXPECT_TRUE(slices.ok()) << slices.message;
  const PlanLayersResult plan = planLayers(slices, planarOptions(settings));
  EXPECT_TRUE(plan.ok()) << plan.message;
  out.moves = plan.toolpath.moves.size();

  ProgramInfo info;
  info.machine = cartesian3Profile(settings.bedSize, settings.nozzleDiameter);
  info.placement = placed.transform;
  info.layerHeight = settings.layerHeight;
  info.lineWidth = settings.effectiveLineWidth();
  info.filamentDiameter = settings.filamentDiameter;
  info.acceleration = settings.acceleration;
  info.settings = listSettings(settings);
  const WriteProgramResult written = writeGcode(plan.toolpath, info);
  EXPECT_TRUE(written.ok()) << written.message;
  // The planner's estimate (planMachineMotion) sums the same terms as toolpathStats().
  const double expectTime = toolpathStats(plan.toolpath, settings.acceleration).estimatedTimeS;
  EXPECT_NEAR(written.estimatedTimeS, expectTime, 1e-9 * expectTime);

  const ParsedProgram program = readProgram(written.text);
  EXPECT_TRUE(program.ok()) << program.message;
  // The header's placement brings the input mesh into the part frame.
  for (size_t i = 0; i < prepared.vertexCount(); i += 97) {
    const Eigen::Vector4d v = program.placement * prepared.vertex(i).homogeneous();
    EXPECT_LT((v.head<3>() - placed.mesh.vertex(i)).norm(), 1e-6) << "vertex " << i;
  }
  const auto t0 = std::chrono::steady_clock::now();
  out.report = verifyProgram(program, placed.mesh);
  out.verifySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(out.report.ok()) << out.report.message;
  // Layers = distinct layer indices of the plan (a slice layer too thin to print has none).
  std::set<int> layerIds;
  for (const Move& m : plan.toolpath.moves) layerIds.insert(m.layer);
  EXPECT_EQ(out.report.layers, int(layerIds.size()));
  EXPECT_LE(out.report.layers, int(slices.layers.size()));
  std::printf("%s fit %.0f mm, infill %.0f %%: %zu moves, verify %.2f s: %s\n", file.c_str(), fitMm,
              infill, out.moves, out.verifySeconds, verifyReportJson(out.report).c_str());
  return out;
}

TEST(VerifyProgram, EndToEndKittenSolid) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const EndToEnd e = sliceAndVerify("pymdp_kitten.off", UpAxis::PosY, 30, 100);
  EXPECT_GE(e.report.inside, 0.99);
  EXPECT_GE(e.report.coverage, 0.95);
  EXPECT_EQ(e.report.collisions, 0u);
  EXPECT_EQ(e.report.limitViolations, 0u);
}

TEST(VerifyProgram, EndToEndBunnySolidAndSparse) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const EndToEnd solid = sliceAndVerify("compas_bunny_closed_low_res.obj", UpAxis::PosZ, 30, 100);
  EXPECT_GE(solid.report.inside, 0.99);
  EXPECT_GE(solid.report.coverage, 0.95);
  EXPECT_EQ(solid.report.collisions, 0u);
  // Sparse infill lowers coverage by design (PROGRAM-FORMAT.md); inside stays.
  const EndToEnd sparse = sliceAndVerify("compas_bunny_closed_low_res.obj", UpAxis::PosZ, 30, 20);
  EXPECT_GE(sparse.report.inside, 0.99);
  EXPECT_LT(sparse.report.coverage, solid.report.coverage - 0.1);
}

}  // namespace
}  // namespace omnislice
