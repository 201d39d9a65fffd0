// SPDX-License-Identifier: MIT
// Issue 7 end to end: `method = multidir` (paper 000) from a mesh to a verified 3+2 program: the
// plane search, closed parts in print order, each sliced along its own direction, the motion
// planner's safe rotations between parts, `verify` on the program.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "test_meshes.h"
#include "pipeline_fixtures.h"
#include "slice_and_verify.h"
#include "pipeline/pipeline.h"
#include "test_support.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

using test::Sliced;
using test::sliceAndVerify;

Settings multidirSettings(const std::string& machine) {
  Settings s;
  s.method = Method::Multidir;
  s.machine = machine;
  s.layerHeight = 0.3;
  s.infillPercent = 100;  // coverage is judged on solid prints
  return s;
}

// What every multidir program keeps: parts in print order, each extruding move of a part lies
// above its base plane, and every part printed earlier lies below the base plane of every later
// one (the inverse order of clipping: the nozzle never reaches back into printed parts); the part
// volumes sum to the solid's; each part prints along its plane's normal.
void expectConsistentParts(const Sliced& r, double layerHeight) {
  ASSERT_TRUE(r.report.contains("multidir")) << r.report.dump();
  const Json& m = r.report["multidir"];
  const Json& parts = m["parts"];
  ASSERT_EQ(parts.size(), m["part_count"].get<size_t>());
  double volume = 0;
  for (const Json& p : parts) volume += p["volume_mm3"].get<double>();
  EXPECT_NEAR(volume, m["volume_mm3"].get<double>(), 1e-6 * m["volume_mm3"].get<double>());
  EXPECT_TRUE(parts[0]["plane"].is_null());
  // Extruding segments per part from the preview (positions, features != 0) and the toolpath's
  // part ids are not in the preview: use the report's per-part layer ranges instead.
  const SlicePreview& pv = r.out.preview;
  std::vector<int> firstLayer;
  int layer = 0;
  for (const Json& p : parts) {
    firstLayer.push_back(layer);
    layer += p["layers"].get<int>();
  }
  firstLayer.push_back(layer);
  auto partOfLayer = [&](uint32_t l) {
    for (size_t i = 0; i + 1 < firstLayer.size(); ++i)
      if (int(l) >= firstLayer[i] && int(l) < firstLayer[i + 1]) return int(i);
    return -1;
  };
  size_t checked = 0;
  for (size_t sgm = 0; sgm < pv.toolpath.features.size(); ++sgm) {
    if (pv.toolpath.features[sgm] == 0) continue;
    const int i = partOfLayer(pv.toolpath.layers[sgm]);
    ASSERT_GE(i, 0);
    const Eigen::Vector3d q(pv.toolpath.positions[6 * sgm + 3], pv.toolpath.positions[6 * sgm + 4], pv.toolpath.positions[6 * sgm + 5]);
    for (size_t k = 1; k < parts.size(); ++k) {
      const Json& plane = parts[k]["plane"];
      const Eigen::Vector3d n(plane["normal"][0], plane["normal"][1], plane["normal"][2]);
      const double d = plane["offset_mm"].get<double>();
      if (int(k) == i) {
        EXPECT_GE(n.dot(q), d - 1e-6) << "part " << i << " below its base plane";
      }
      // An earlier part reaches across a later part's plane (multidir.interface_overlap) but its
      // tips stay under the later part's first tips, h/2 above the plane.
      if (int(k) > i) {
        EXPECT_LE(n.dot(q), d + 0.5 * layerHeight + 1e-6) << "part " << i << " above the plane of later part " << k;
      }
    }
    // The nozzle axis of a part is its direction.
    const Eigen::Vector3d u(pv.toolpath.axes[3 * sgm], pv.toolpath.axes[3 * sgm + 1], pv.toolpath.axes[3 * sgm + 2]);
    const Json& dir = parts[size_t(i)]["direction"];
    EXPECT_NEAR(u.dot(Eigen::Vector3d(dir[0], dir[1], dir[2])), 1.0, 1e-4);
    ++checked;
  }
  EXPECT_GT(checked, 100u);
}

void expectVerified(const Sliced& r) {
  ASSERT_FALSE(r.verify.is_null());
  EXPECT_GE(r.verify["inside"].get<double>(), 0.99) << r.verify.dump();
  EXPECT_EQ(r.verify["collisions"].get<int>(), 0) << r.verify.dump();
  EXPECT_EQ(r.verify["limits"].get<int>(), 0) << r.verify.dump();
  EXPECT_GE(r.verify["coverage"].get<double>(), 0.98) << r.verify.dump();
}

// The planar print without supports (support = none: auto would add them under the overhang).
double planarSupported(const std::vector<uint8_t>& bytes, const std::string& name, Settings s) {
  s.method = Method::Planar;
  s.support.mode = SupportMode::None;
  const Sliced r = sliceAndVerify(bytes, name, s);
  return r.verify.is_null() ? 1.0 : r.verify["supported"].get<double>();
}

// An L-bracket (a column with an arm at the top): one tilted cut prints the arm along its own
// direction, no risky face is left, and the program is fully supported where the planar print of
// the same bracket is not.
TEST(MultidirPipeline, LBracketOneCutIsSupportFreeOnTheTable) {
  const Mesh l = test::makeLBracket(10);
  const std::vector<uint8_t> bytes = test::binaryStl(l);
  Settings s = multidirSettings("table5");
  // 0.2 mm layers: verify's reach 1.5 h = 0.3 mm is then below the solid line spacing (0.41 mm),
  // so a bridged layer shows as unsupported (at 0.3 mm layers the reach, 0.45 mm, spans the
  // spacing and counts each bridging line as held by its neighbour).
  s.layerHeight = 0.2;
  const Sliced r = sliceAndVerify(bytes, "l.stl", s);
  if (!r.out.ok()) return;
  expectConsistentParts(r, s.layerHeight);
  const Json& m = r.report["multidir"];
  std::printf("L: %s\nverify %s\n", m.dump().substr(0, 900).c_str(), r.verify.dump().c_str());
  EXPECT_NEAR(m["J_G_before"].get<double>(), 200.0, 1e-6);  // the arm's underside, 20 x 10 mm
  EXPECT_LT(m["J_G_after"].get<double>(), 1e-6);
  EXPECT_GE(m["part_count"].get<int>(), 2);
  expectVerified(r);
  const double planar = planarSupported(bytes, "l.stl", s);
  EXPECT_LT(planar, 0.97);
  EXPECT_GE(r.verify["supported"].get<double>(), 0.99) << "planar " << planar;
  EXPECT_GE(r.report["motion"]["safe_rotations"].get<int>(), 1);
}

// The preview buffers for the page: every part's closed mesh with its print index per triangle,
// and risky flags per triangle of the placed part whose areas give J_G before and after.
TEST(MultidirPipeline, PreviewBuffersHoldPartsAndRiskyFaces) {
  const Mesh l = test::makeLBracket(10);
  const std::vector<uint8_t> bytes = test::binaryStl(l);
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", multidirSettings("table5"));
  ASSERT_TRUE(out.ok()) << out.message;
  const Json m = Json::parse(out.reportJson)["multidir"];
  const SlicePreview& p = out.preview;
  ASSERT_EQ(p.method.multidir.partPositions.size() % 3, 0u);
  ASSERT_EQ(p.method.multidir.partTriangles.size(), 3 * p.method.multidir.partIds.size());
  ASSERT_GT(p.method.multidir.partIds.size(), 0u);
  const size_t parts = m["part_count"].get<size_t>();
  std::set<uint32_t> seen;
  for (uint32_t id : p.method.multidir.partIds) {
    EXPECT_LT(id, parts);
    seen.insert(id);
  }
  for (uint32_t v : p.method.multidir.partTriangles) ASSERT_LT(v, p.method.multidir.partPositions.size() / 3);
  EXPECT_EQ(seen.size(), parts) << "every (non-empty) part has triangles";
  // Volume per part from the soup matches the report.
  std::vector<double> volume(parts, 0);
  for (size_t t = 0; t < p.method.multidir.partIds.size(); ++t) {
    Eigen::Vector3d q[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = p.method.multidir.partTriangles[3 * t + size_t(k)];
      q[k] = Eigen::Vector3d(p.method.multidir.partPositions[3 * v], p.method.multidir.partPositions[3 * v + 1], p.method.multidir.partPositions[3 * v + 2]);
    }
    volume[p.method.multidir.partIds[t]] += q[0].dot(q[1].cross(q[2])) / 6;
  }
  for (size_t i = 0; i < parts; ++i) {
    const double want = m["parts"][i]["volume_mm3"].get<double>();
    EXPECT_NEAR(volume[i], want, 1e-3 * std::max(1.0, want)) << "part " << i;
  }
  // Risky flags per triangle of the placed part.
  const Mesh& mesh = out.partMesh;
  ASSERT_EQ(p.method.multidir.riskyBefore.size(), mesh.faceCount());
  ASSERT_EQ(p.method.multidir.riskyAfter.size(), mesh.faceCount());
  double before = 0, after = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const double area = (b - a).cross(c - a).norm() / 2;
    if (p.method.multidir.riskyBefore[f]) before += area;
    if (p.method.multidir.riskyAfter[f]) after += area;
  }
  const double jgBefore = m["J_G_before"].get<double>();
  EXPECT_GT(jgBefore, 0);
  EXPECT_NEAR(before, jgBefore, 0.01 * jgBefore);
  EXPECT_NEAR(after, m["J_G_after"].get<double>(), 0.01 * jgBefore);
}

// A turned 4dof decomposition (rotary4): the flags follow the part as printed, after <= before.
TEST(MultidirPipeline, PreviewRiskyFacesOnRotary) {
  const Mesh t = test::makeBoxUnion({{0, 0, 0, 10, 10, 30}, {0, 10, 20, 10, 25, 30}, {0, -15, 20, 10, 0, 30}});
  const std::vector<uint8_t> bytes = test::binaryStl(t);
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "t.stl", multidirSettings("rotary4"));
  ASSERT_TRUE(out.ok()) << out.message;
  const Json m = Json::parse(out.reportJson)["multidir"];
  const Mesh& mesh = out.partMesh;
  ASSERT_EQ(out.preview.method.multidir.riskyAfter.size(), mesh.faceCount());
  double before = 0, after = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const double area = (b - a).cross(c - a).norm() / 2;
    if (out.preview.method.multidir.riskyBefore[f]) before += area;
    if (out.preview.method.multidir.riskyAfter[f]) after += area;
  }
  const double jgBefore = m["J_G_before"].get<double>();
  EXPECT_NEAR(before, jgBefore, 0.01 * jgBefore);
  EXPECT_NEAR(after, m["J_G_after"].get<double>(), 0.02 * jgBefore);
  EXPECT_LT(after, before);
}

// The paper's Kitten (Y-up, fit 60 mm so the tilted parts stay within table5's reach).
TEST(MultidirPipeline, KittenOnTableVerifiesAndRemovesItsOverhang) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / "pymdp_kitten.off");
  Settings s = multidirSettings("table5");
  s.placement.up = UpAxis::PosY;
  s.placement.fitMm = 60;
  const Sliced r = sliceAndVerify(bytes, "kitten.off", s);
  if (!r.out.ok()) return;
  expectConsistentParts(r, s.layerHeight);
  const Json& m = r.report["multidir"];
  std::printf("kitten: %s\nverify %s\n", m.dump().substr(0, 1200).c_str(), r.verify.dump().c_str());
  EXPECT_LT(m["J_G_after"].get<double>(), 0.1 * m["J_G_before"].get<double>());
  expectVerified(r);
  // Issue 7: with supports (the default) supported >= 0.99. The planar print of this Kitten reads
  // 0.9997 (verify's reach of 1.5 h holds overhangs up to ~56 deg at 0.3 mm layers), so both sit
  // within a few dozen samples of 1 and are printed for the record, not compared. The multidir
  // print's unsupported samples (measured: ~40, the planar print's ~20) lie in one part's outer
  // wall 0.2 mm under a later part's cut plane, along the two lines where that plane meets the
  // body: their corner moves ~0.4 mm per layer (an edge ~53 deg from the part's direction) though
  // neither the body's faces (35-42 deg) nor the plane is risky by Eq. 1.
  EXPECT_GE(r.verify["supported"].get<double>(), 0.99);
  const double planar = planarSupported(bytes, "kitten.off", s);
  std::printf("kitten supported: with supports %.5f, planar without %.5f\n", r.verify["supported"].get<double>(),
              planar);
}

// Issue 7 item 9: the page draws J_G per search level while the search runs. The Kitten as the
// README's CLI example slices it (Y-up, robot6): the progress reports' chosen levels are the
// report's search.J_G_per_level (same count, same values), the search lines report one level per
// level the search expanded (search.levels), each line's J_G never rises and starts at J_G
// before; cancelling on a level of the beam line ends the slice with Cancelled.
TEST(MultidirPipeline, KittenSearchLevelsMatchTheReport) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / "pymdp_kitten.off");
  Settings s;
  s.method = Method::Multidir;
  s.machine = "robot6";
  s.placement.up = UpAxis::PosY;
  struct Level {
    std::string line;
    int level;
    double jg;
  };
  std::vector<Level> levels;
  std::vector<std::string> stagesAfterChosen;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "pymdp_kitten.off", s, [&](const ProgressEvent& e) {
    if (e.search) {
      EXPECT_STREQ(e.stage, "decompose");
      levels.push_back({e.search->line, e.search->level, e.search->jgMm2});
    } else if (!levels.empty() && levels.back().line == "chosen") {
      stagesAfterChosen.push_back(e.stage);
    }
    return true;
  });
  ASSERT_TRUE(out.ok()) << out.message;
  const Json m = Json::parse(out.reportJson)["multidir"];
  const std::vector<double> perLevel = m["search"]["J_G_per_level"].get<std::vector<double>>();
  std::vector<double> chosen;
  size_t searched = 0;
  // One run per search line in order (each restart of the beam is a line of its own).
  std::vector<std::pair<std::string, std::vector<double>>> runs;
  for (const Level& l : levels) {
    if (l.line == "chosen") {
      EXPECT_EQ(l.level, static_cast<int>(chosen.size()));
      chosen.push_back(l.jg);
      continue;
    }
    EXPECT_TRUE(chosen.empty()) << "a " << l.line << " level after the chosen sequence";
    searched += l.level >= 1 ? 1 : 0;
    if (l.level == 0) runs.push_back({l.line, {}});
    ASSERT_FALSE(runs.empty());
    EXPECT_EQ(runs.back().first, l.line) << "a line's levels are not contiguous";
    std::vector<double>& run = runs.back().second;
    EXPECT_EQ(l.level, static_cast<int>(run.size())) << l.line;
    if (run.empty()) {
      EXPECT_EQ(l.jg, m["J_G_before"].get<double>()) << l.line;
    }
    if (!run.empty()) {
      EXPECT_LE(l.jg, run.back()) << l.line << " level " << l.level;
    }
    run.push_back(l.jg);
  }
  std::vector<std::string> names;
  for (const auto& run : runs) {
    names.push_back(run.first);
    std::printf("kitten search line %s: %zu levels\n", run.first.c_str(), run.second.size());
  }
  std::printf("kitten chosen %zu, report %zu\n", chosen.size(), perLevel.size());
  std::vector<std::string> expected = {"greedy", "constrained"};
  const size_t restartsRun = m["search"]["restarts_run"].get<size_t>();
  EXPECT_GE(restartsRun, 1u);
  EXPECT_LE(restartsRun, static_cast<size_t>(s.multidir.restarts));
  expected.insert(expected.end(), restartsRun, "beam");
  EXPECT_EQ(names, expected);
  ASSERT_EQ(chosen.size(), perLevel.size());
  for (size_t k = 0; k < chosen.size(); ++k) EXPECT_EQ(chosen[k], perLevel[k]) << "level " << k;
  EXPECT_EQ(chosen.back(), m["J_G_after"].get<double>());
  EXPECT_EQ(searched, m["search"]["levels"].get<size_t>());
  EXPECT_FALSE(stagesAfterChosen.empty());
  EXPECT_NE(std::find(stagesAfterChosen.begin(), stagesAfterChosen.end(), "clip"), stagesAfterChosen.end());

  bool cancelled = false;
  const SliceOutput stopped = runSlice(bytes.data(), bytes.size(), "pymdp_kitten.off", s, [&](const ProgressEvent& e) {
    EXPECT_FALSE(cancelled) << "a report after the cancel (" << e.stage << ")";
    cancelled = e.search && std::string(e.search->line) == "beam" && e.search->level == 2;
    return !cancelled;
  });
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(stopped.status, Status::Cancelled);
}

// rotary4 (one stepper axis about X, +-60 degrees): every part direction is orthogonal to X,
// within the range and on the stepper grid.
TEST(MultidirPipeline, RotaryFourDofDirectionsStayOnTheAxisGrid) {
  const Mesh t = test::makeBoxUnion({{0, 0, 0, 10, 10, 30}, {0, 10, 20, 10, 25, 30}, {0, -15, 20, 10, 0, 30}});
  const std::vector<uint8_t> bytes = test::binaryStl(t);
  Settings s = multidirSettings("rotary4");
  const Sliced r = sliceAndVerify(bytes, "t.stl", s);
  if (!r.out.ok()) return;
  expectConsistentParts(r, s.layerHeight);
  const Json& m = r.report["multidir"];
  std::printf("T on rotary4: %s\nverify %s\n", m.dump().substr(0, 900).c_str(), r.verify.dump().c_str());
  EXPECT_EQ(m["dof"], "4dof");
  EXPECT_LT(m["J_G_after"].get<double>(), 0.1 * m["J_G_before"].get<double>());
  for (const Json& p : m["parts"]) {
    const Eigen::Vector3d d(p["direction"][0], p["direction"][1], p["direction"][2]);
    EXPECT_NEAR(d.x(), 0, 1e-9);
    EXPECT_LE(std::acos(std::clamp(d.z(), -1.0, 1.0)) * 180 / M_PI, 60 + 1e-6);
  }
  expectVerified(r);
}

TEST(MultidirPipeline, RefusesBadSetUps) {
  const std::vector<uint8_t> box = test::binaryStl(test::makeBox(-8, -8, 0, 8, 8, 12));
  Settings s = multidirSettings("cartesian3");
  EXPECT_EQ(runSlice(box.data(), box.size(), "box.stl", s).status, Status::InvalidOption);
  s.machine = "table5";
  Settings c = s;
  ASSERT_TRUE(setSetting(c, "multidir.dof", "4dof").ok());
  EXPECT_EQ(runSlice(box.data(), box.size(), "box.stl", c).status, Status::InvalidOption);
  EXPECT_FALSE(setSetting(c, "multidir.scheme", "random").ok());
  EXPECT_FALSE(setSetting(c, "multidir.alpha_max_deg", "90").ok());
  EXPECT_FALSE(setSetting(c, "multidir.beam_width", "0").ok());
  EXPECT_FALSE(setSetting(c, "multidir.perturbations", "-1").ok());
  EXPECT_FALSE(setSetting(c, "multidir.perturbations", "10001").ok());
  EXPECT_FALSE(setSetting(c, "multidir.perturbations", "many").ok());
  EXPECT_TRUE(setSetting(c, "multidir.perturbations", "0").ok());
  EXPECT_FALSE(setSetting(c, "multidir.w", "nan").ok());
  // An open mesh is not a solid: refused with repair = none, closed and printed with auto.
  Mesh open = test::makeBox(-8, -8, 0, 8, 8, 12);
  open.triangles.resize(open.triangles.size() - 3);
  const std::vector<uint8_t> bytes = test::binaryStl(open);
  Settings none = s;
  ASSERT_TRUE(setSetting(none, "repair", "none").ok());
  EXPECT_EQ(runSlice(bytes.data(), bytes.size(), "open.stl", none).status, Status::OpenMesh);
  const SliceOutput repaired = runSlice(bytes.data(), bytes.size(), "open.stl", s);
  ASSERT_TRUE(repaired.ok()) << repaired.message;
  EXPECT_EQ(Json::parse(repaired.reportJson)["mesh"]["repair"]["holes_filled"].get<int>(), 1);
  // A box needs no cut: one part, the planar print.
  const SliceOutput one = runSlice(box.data(), box.size(), "box.stl", s);
  ASSERT_TRUE(one.ok()) << one.message;
  const Json m = Json::parse(one.reportJson)["multidir"];
  EXPECT_EQ(m["part_count"].get<int>(), 1);
  EXPECT_EQ(m["J_G_after"].get<double>(), 0.0);
}

TEST(MultidirPipeline, CancelStopsInEveryStage) {
  const Mesh l = test::makeLBracket(10);
  const std::vector<uint8_t> bytes = test::binaryStl(l);
  const Settings s = multidirSettings("table5");
  std::set<std::string> seen;
  SliceOutput full = runSlice(bytes.data(), bytes.size(), "l.stl", s, [&](const char* stage, double) {
    seen.insert(stage);
    return true;
  });
  ASSERT_TRUE(full.ok()) << full.message;
  for (const char* stage : {"decompose", "clip", "motion", "program"}) {
    EXPECT_TRUE(seen.count(stage)) << stage;
    SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s, [&](const char* st, double) {
      return std::string(st) != stage;
    });
    EXPECT_EQ(out.status, Status::Cancelled) << stage;
  }
}

}  // namespace
}  // namespace omnislice
