// SPDX-License-Identifier: MIT
// Issue 6 end to end: the geodesic method of paper 002 (`method = geodesic`) from a shared `.tet`
// model and from a closed mesh meshed by Omnislice, through the IGDS, the skeleton tree, the
// three traversals and Fermat-spiral filling paths, to programs that pass `verify`.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "../test_meshes.h"
#include "../test_support.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"
#include "slice_and_verify.h"
#include "toolpath/toolpath.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

Settings geodesicSettings(const std::string& machine, double interval) {
  Settings s;
  s.method = Method::Geodesic;
  s.machine = machine;
  s.nozzleDiameter = 0.8;
  s.layerHeight = interval;
  s.lineWidth = 0.9;
  // These tests check the method's own properties against `omnislice verify`'s figures; a
  // program short of the strict soundness criteria (pipeline/soundness.h) is still delivered
  // here (soundness_test.cpp tests the refusal).
  s.verify = VerifyMode::Warn;
  return s;
}

// compas_branches_16 fitted to 80 mm through Omnislice's own ~30k tets, 0.8 mm layers.
std::vector<uint8_t> branchesBytes() {
  return test::readBytes(test::sharedModelsDir() / "compas_branches_16_closed_mid_res.stl");
}
Settings branchesSettings(const std::string& machine) {
  Settings s = geodesicSettings(machine, 0.8);
  s.placement.fitMm = 80;
  s.geodesic.targetTets = 30000;
  return s;
}

using test::Sliced;
using test::sliceAndVerify;

// Properties every geodesic slice keeps: the sequence visits every skeleton node once and never
// before its lower-nodes (Criterion 1), the preview carries the field and the tree, the report
// carries the three traversals.
void expectConsistent(const Sliced& r) {
  ASSERT_TRUE(r.report.contains("geodesic")) << r.report.dump();
  const Json& g = r.report["geodesic"];
  const SlicePreview& p = r.out.preview;
  const size_t nodes = p.method.geodesic.nodeLayers.size();
  EXPECT_EQ(g["igds"].get<size_t>(), nodes);
  EXPECT_EQ(p.method.geodesic.nodePositions.size(), 3 * nodes);
  ASSERT_EQ(p.method.geodesic.sequence.size(), nodes);
  std::vector<size_t> position(nodes, SIZE_MAX);
  for (size_t k = 0; k < nodes; ++k) {
    ASSERT_LT(p.method.geodesic.sequence[k], nodes);
    EXPECT_EQ(position[p.method.geodesic.sequence[k]], SIZE_MAX) << "node printed twice";
    position[p.method.geodesic.sequence[k]] = k;
  }
  for (size_t e = 0; e + 1 < p.method.geodesic.treeEdges.size(); e += 2) {
    const uint32_t lower = p.method.geodesic.treeEdges[e], upper = p.method.geodesic.treeEdges[e + 1];
    EXPECT_EQ(p.method.geodesic.nodeLayers[upper], p.method.geodesic.nodeLayers[lower] + 1);
    EXPECT_LT(position[lower], position[upper]) << "Criterion 1";
  }
  EXPECT_EQ(p.method.geodesic.fieldValues.size() * 3, p.method.geodesic.fieldPositions.size());
  EXPECT_GT(p.method.geodesic.fieldTriangles.size(), 0u);
  EXPECT_FALSE(p.method.surfaces.layers.empty());
  for (const char* k : {"LPT", "DPT", "A3"}) {
    ASSERT_TRUE(g["traversals"].contains(k)) << g.dump();
  }
  EXPECT_EQ(g["overhang_avg_deg"].size(), g["layers"].get<size_t>());
  EXPECT_EQ(g["overhang_ratio"].size(), g["layers"].get<size_t>());
}

void expectVerified(const Sliced& r, double supported) {
  ASSERT_FALSE(r.verify.is_null());
  EXPECT_GE(r.verify["inside"].get<double>(), 0.99) << r.verify.dump();
  EXPECT_EQ(r.verify["collisions"].get<int>(), 0) << r.verify.dump();
  EXPECT_EQ(r.verify["limits"].get<int>(), 0) << r.verify.dump();
  EXPECT_GE(r.verify["supported"].get<double>(), supported) << r.verify.dump();
}

// A tet model from ../shared (Y-up, the platform at min y), its own tets, on the robot.
TEST(GeodesicPipeline, YogaTetFileOnRobotVerifies) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / "reinforcedfdm_YogaNew.tet");
  Settings s = geodesicSettings("robot6-ur5", 0.8);
  s.placement.up = UpAxis::PosY;
  s.placement.fitMm = 80;
  // The paper's field, whose loop closure leaves path out (the subject of this test); with the
  // default alignment (geodesic.align_passes) it leaves none.
  s.geodesic.alignPasses = 0;
  s.geodesic.alignRetryPasses = 0;
  s.geodesic.maxThicknessRatio = 1;
  const Sliced r = sliceAndVerify(bytes, "yoga.tet", s);
  if (!r.out.ok()) return;
  expectConsistent(r);
  const Json& g = r.report["geodesic"];
  EXPECT_EQ(g["tet_source"], "input");
  EXPECT_EQ(g["tets"].get<size_t>(), 52446u);
  std::printf("yoga: %s\nverify %s\n", g.dump().substr(0, 1500).c_str(), r.verify.dump().c_str());
  expectVerified(r, 0.99);

  // Two limbs meet at the top of the part and close a loop: the two growth fronts meet there and
  // the last gap faces the nozzle from both sides, so some tool path is left out. The user is told how much
  // and where (report warning, CLI line, page), and the preview holds exactly those segments,
  // none of which the program prints.
  const size_t skipped = g["skipped_segments"].get<size_t>();
  ASSERT_GT(skipped, 0u) << "the loop closure of this model skips no path any more: update this test";
  const std::vector<float>& seg = r.out.preview.method.geodesic.skippedSegments;
  ASSERT_EQ(seg.size(), 6 * skipped);
  ASSERT_EQ(r.out.preview.method.geodesic.skippedLayers.size(), skipped);
  double length = 0, zLo = 1e9, zHi = -1e9;
  // The printed segments of the preview (feature != travel), against each skipped one's middle.
  const std::vector<float>& pos = r.out.preview.toolpath.positions;
  const std::vector<uint8_t>& feature = r.out.preview.toolpath.features;
  auto nearestPrinted = [&](const Eigen::Vector3d& q) {
    double best = 1e9;
    for (size_t i = 0; i < feature.size(); ++i) {
      if (feature[i] == 0) continue;
      const Eigen::Vector3d a(pos[6 * i], pos[6 * i + 1], pos[6 * i + 2]), b(pos[6 * i + 3], pos[6 * i + 4], pos[6 * i + 5]);
      const Eigen::Vector3d ab = b - a;
      const double t = ab.squaredNorm() > 0 ? std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
      best = std::min(best, (q - a - t * ab).norm());
    }
    return best;
  };
  for (size_t k = 0; k < skipped; ++k) {
    const Eigen::Vector3d a(seg[6 * k], seg[6 * k + 1], seg[6 * k + 2]), b(seg[6 * k + 3], seg[6 * k + 4], seg[6 * k + 5]);
    length += (b - a).norm();
    zLo = std::min({zLo, a.z(), b.z()});
    zHi = std::max({zHi, a.z(), b.z()});
    // A printed segment through the middle (the planner may split moves) would be this one; the
    // nearest other beads come within ~0.1 mm where spiral turns join.
    if (k % 4 == 0) {
      EXPECT_GT(nearestPrinted(0.5 * (a + b)), 0.01) << "skipped segment " << k << " is printed";
    }
  }
  EXPECT_NEAR(length, g["skipped_mm"].get<double>(), 1e-3 * length);
  // Where the limbs meet: the top of the part (fit 80 mm of height).
  EXPECT_GT(zLo, 60.0);
  const Json& layers = g["skipped_layers"];
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_LE(layers[0].get<int>(), layers[1].get<int>());
  EXPECT_LT(layers[1].get<int>(), g["layers"].get<int>());
  const auto [lowest, highest] = std::minmax_element(r.out.preview.method.geodesic.skippedLayers.begin(), r.out.preview.method.geodesic.skippedLayers.end());
  EXPECT_EQ(*lowest, layers[0].get<uint32_t>());
  EXPECT_EQ(*highest, layers[1].get<uint32_t>());
  // The method's warnings (the left-out path first; bead_on_platform where the first layers reach
  // the bed), then the verification's: tool path left out is unsound (verify = warn).
  ASSERT_GE(r.out.warnings.size(), 2u);
  EXPECT_EQ(r.out.warnings[0].code, "skipped_tool_path");
  for (size_t i = 1; i + 1 < r.out.warnings.size(); ++i) EXPECT_EQ(r.out.warnings[i].code, "bead_on_platform");
  EXPECT_EQ(r.out.warnings.back().code, "unsound_program");
  EXPECT_NE(r.out.warnings.back().message.find("of tool path is left out"), std::string::npos);
  EXPECT_EQ(r.report["warnings"][0]["code"], "skipped_tool_path");
  EXPECT_EQ(r.report["warnings"][0]["message"], r.out.warnings[0].message);
  const std::string where = "layers " + std::to_string(layers[0].get<int>() + 1) + "-" + std::to_string(layers[1].get<int>() + 1);
  EXPECT_NE(r.out.warnings[0].message.find(where), std::string::npos) << r.out.warnings[0].message;
  std::printf("warning: %s (z %.1f..%.1f)\n", r.out.warnings[0].message.c_str(), zLo, zHi);
}

// The shared kitten (Y up) at 60 mm through Omnislice's own ~30k tets, 0.8 mm layers, table5.
Settings meshedKittenSettings() {
  Settings s = geodesicSettings("table5", 0.8);
  s.placement.up = UpAxis::PosY;
  s.placement.fitMm = 60;
  s.geodesic.targetTets = 30000;
  return s;
}

// A closed mesh meshed by Omnislice, on the tilting table.
TEST(GeodesicPipeline, MeshedKittenOnTableVerifies) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / "pymdp_kitten.off");
  Settings s = meshedKittenSettings();
  const Sliced r = sliceAndVerify(bytes, "kitten.off", s);
  if (!r.out.ok()) return;
  expectConsistent(r);
  const Json& g = r.report["geodesic"];
  EXPECT_EQ(g["tet_source"], "mesher");
  std::printf("kitten: %s\nverify %s\n", g.dump().substr(0, 1500).c_str(), r.verify.dump().c_str());
  expectVerified(r, 0.99);
}

// Issue 33's motion term (motion.axis_freedom_deg, geodesic default 25): against the ideal axes (0) the
// same layers print with the rotary axes turning less and sooner done, as soundly (verify's
// collisions and left-out material, and supported within a point), every axis within the
// freedom of its ideal as the report counts them.
TEST(GeodesicPipeline, AxisFreedomTurnsTheTableLessAsSoundly) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / "pymdp_kitten.off");
  Settings s = meshedKittenSettings();
  s.verifyAttempts = 1;
  const Sliced freed = sliceAndVerify(bytes, "kitten.off", s);
  s.axisFreedomDegrees = 0;
  const Sliced ideal = sliceAndVerify(bytes, "kitten.off", s);
  if (!freed.out.ok() || !ideal.out.ok()) return;
  const double rotFreed = freed.report["motion"]["pose_cost"], rotIdeal = ideal.report["motion"]["pose_cost"];
  const double tFreed = freed.report["estimated_time_s"], tIdeal = ideal.report["estimated_time_s"];
  std::printf("axis freedom 25 (geodesic default) / 0: rotary %.0f / %.0f deg, time %.0f / %.0f s, axes freed %zu\n", rotFreed, rotIdeal,
              tFreed, tIdeal, freed.report["geodesic"]["axes_freed"].get<size_t>());
  EXPECT_EQ(ideal.report["geodesic"]["axes_freed"], 0);
  EXPECT_GT(freed.report["geodesic"]["axes_freed"].get<size_t>(), 0u);
  EXPECT_LT(rotFreed, 0.75 * rotIdeal);
  EXPECT_LT(tFreed, 0.9 * tIdeal);
  EXPECT_EQ(freed.verify["collisions"], 0);
  EXPECT_LE(freed.report["verify"]["left_out_mm"].get<double>(), ideal.report["verify"]["left_out_mm"].get<double>() + 1e-9);
  EXPECT_GE(freed.verify["supported"].get<double>(), ideal.verify["supported"].get<double>() - 0.01);
}

// The default geodesic program of the shared coin at 40 mm on table5 (axis freedom 25, 40
// alignment passes): with the motion term's axes one path leaves 1 mm of tool path out (the
// 50-pass retry field too: measured with the retry switched off), so that path is oriented again
// near its ideal axes where it left segments out, and then nothing is left out: the first program
// is sound, as `omnislice verify` finds it on its own, and the axes still lean for motion.
TEST(GeodesicPipeline, LeftOutPathRetriedNearItsIdealAxes) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes =
      test::readBytes(test::sharedModelsDir() / "compas_overhang_coin_closed_low_res.stl");
  Settings s;
  s.method = Method::Geodesic;
  s.machine = "table5";
  s.placement.fitMm = 40;
  s.verify = VerifyMode::Warn;
  s.verifyAttempts = 1;
  const Sliced r = sliceAndVerify(bytes, "coin.stl", s);
  if (!r.out.ok()) return;
  const Json& g = r.report["geodesic"];
  std::printf("coin 40 mm: near-ideal paths %zu, skipped %.2f mm, axes freed %zu, %.2f h\n",
              g["near_ideal_paths"].get<size_t>(), g["skipped_mm"].get<double>(), g["axes_freed"].get<size_t>(),
              r.report["estimated_time_s"].get<double>() / 3600);
  EXPECT_EQ(g["axis_freedom_deg"].get<double>(), 25);
  EXPECT_GE(g["near_ideal_paths"].get<size_t>(), 1u);
  EXPECT_EQ(g["skipped_segments"].get<size_t>(), 0u);
  EXPECT_FALSE(g["align_retry"]["retried"].get<bool>());
  EXPECT_GT(g["axes_freed"].get<size_t>(), 1000u);
  EXPECT_TRUE(r.report["verify"]["sound"].get<bool>()) << r.report["verify"].dump();
  EXPECT_EQ(r.report["verify"]["left_out_mm"].get<double>(), 0.0);
  expectVerified(r, 0.99);
}

// Boundary ears folded against their layer in the preview's IGDS surfaces: a triangle whose apex
// belongs to it alone, turned more than 45 degrees from the triangle across its base, the apex
// within a quarter of the base from the base's line.
size_t foldedEars(const SlicePreview& p) {
  const size_t nv = p.method.surfaces.positions.size() / 3, nt = p.method.surfaces.triangles.size() / 3;
  auto vertex = [&](uint32_t v) {
    return Eigen::Vector3d(p.method.surfaces.positions[3 * v], p.method.surfaces.positions[3 * v + 1], p.method.surfaces.positions[3 * v + 2]);
  };
  auto normal = [&](size_t t) {
    const uint32_t* f = &p.method.surfaces.triangles[3 * t];
    return Eigen::Vector3d((vertex(f[1]) - vertex(f[0])).cross(vertex(f[2]) - vertex(f[0])));
  };
  std::vector<uint32_t> valence(nv, 0);
  std::map<std::pair<uint32_t, uint32_t>, std::vector<size_t>> edgeFaces;
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = p.method.surfaces.triangles[3 * t + k], b = p.method.surfaces.triangles[3 * t + (k + 1) % 3];
      ++valence[a];
      edgeFaces[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  size_t folded = 0;
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t c = p.method.surfaces.triangles[3 * t + k], a = p.method.surfaces.triangles[3 * t + (k + 1) % 3],
                     b = p.method.surfaces.triangles[3 * t + (k + 2) % 3];
      const std::vector<size_t>& across = edgeFaces[{std::min(a, b), std::max(a, b)}];
      if (valence[c] != 1 || across.size() != 2) continue;
      const size_t other = across[0] == t ? across[1] : across[0];
      const double base = (vertex(b) - vertex(a)).norm();
      const double height = (vertex(c) - vertex(a)).cross(vertex(b) - vertex(a)).norm() / base;
      const Eigen::Vector3d n1 = normal(t), n2 = normal(other);
      if (height <= 0.25 * base && n1.dot(n2) < std::sqrt(0.5) * n1.norm() * n2.norm()) ++folded;
    }
  return folded;
}

// The overhang coin (a disc standing on its edge, two flat faces) through Omnislice's own tets.
// Remeshing left boundary ears lying in the flat faces (their normal across the layer, 18 of 97
// ears at fit 80 and 0.6 mm): the collision envelope of their apex swept over the layers printed
// before, so 11 nodes collided in every order (at any nozzle angle, 10 degrees included). Folded
// ears are dropped now: none is left, and every order of the coin is collision-free.
TEST(GeodesicPipeline, CoinLayersKeepNoFoldedEarAndPrintCollisionFree) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes =
      test::readBytes(test::sharedModelsDir() / "compas_overhang_coin_closed_low_res.stl");
  Settings s = geodesicSettings("table5", 0.6);
  s.placement.fitMm = 80;
  // The paper's field (t = h^2, no alignment, whole-interval steps), where the ears were found.
  s.geodesic.heatTime = 1;
  s.geodesic.alignPasses = 0;
  s.geodesic.alignRetryPasses = 0;
  s.geodesic.maxThicknessRatio = 1;
  const Sliced r = sliceAndVerify(bytes, "coin.stl", s);
  if (!r.out.ok()) return;
  expectConsistent(r);
  EXPECT_EQ(foldedEars(r.out.preview), 0u);
  const Json& t = r.report["geodesic"]["traversals"];
  std::printf("coin traversals %s\nverify %s\n", t.dump().c_str(), r.verify.dump().c_str());
  for (const char* kind : {"LPT", "DPT", "A3"}) EXPECT_EQ(t[kind]["unavoidable_nodes"].get<int>(), 0) << kind;
  EXPECT_TRUE(t["A3"]["collision_free"].get<bool>());
  EXPECT_EQ(t["A3"]["colliding_nodes"].get<int>(), 0);
  EXPECT_LE(t["A3"]["retractions"].get<int>(), t["LPT"]["retractions"].get<int>());
  EXPECT_LE(t["A3"]["air_move_mm"].get<double>(), t["LPT"]["air_move_mm"].get<double>());
  expectVerified(r, 0.99);
}

// A branching tree (the paper's Section 4.2 experiment) through Omnislice's own tets. Its 16
// struts touch (21 merge nodes): where two fronts close a loop, a node's potential collision
// surfaces hold its own ancestors and no order avoids that collision (unavoidable_nodes). A3
// then collides only about where LPT does, with far fewer retractions and shorter air moves;
// on a tree without merges it is collision-free (PrintOrderTraversal tests, the demo tree). The
// sequence's collision model takes the paper's nozzle angle (geodesic.nozzle_angle_deg, here a
// slender 15 degrees); the program is verified with the machine's own 40-degree cone, the
// tool-path turning or leaving out what would collide.
TEST(GeodesicPipeline, BranchesA3BeatsLayerPriority) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = branchesBytes();
  Settings s = branchesSettings("table5");
  s.geodesic.nozzleAngleDeg = 15;
  const Sliced r = sliceAndVerify(bytes, "branches.stl", s);
  if (!r.out.ok()) return;
  expectConsistent(r);
  const Json& g = r.report["geodesic"];
  const Json& t = g["traversals"];
  std::printf("branches traversals %s tree %s\nverify %s\n", t.dump().c_str(), g["tree"].dump().c_str(),
              r.verify.dump().c_str());
  EXPECT_GT(g["tree"]["branch_points"].get<int>(), 0);
  const int unavoidable = t["A3"]["unavoidable_nodes"].get<int>();
  EXPECT_EQ(unavoidable, t["LPT"]["unavoidable_nodes"].get<int>());
  EXPECT_GE(t["A3"]["colliding_nodes"].get<int>(), unavoidable);
  EXPECT_LE(t["A3"]["colliding_nodes"].get<int>(), t["LPT"]["colliding_nodes"].get<int>() + unavoidable);
  EXPECT_LT(t["DPT"]["retractions"].get<int>(), t["A3"]["retractions"].get<int>());
  EXPECT_GT(t["DPT"]["colliding_nodes"].get<int>(), 10 * t["A3"]["colliding_nodes"].get<int>());
  EXPECT_LT(5 * t["A3"]["retractions"].get<int>(), t["LPT"]["retractions"].get<int>());
  EXPECT_LT(3 * t["A3"]["air_move_mm"].get<double>(), t["LPT"]["air_move_mm"].get<double>());
  // What the tool-path had to leave out stays small (the loops' last gaps).
  EXPECT_LT(g["skipped_mm"].get<double>(), 0.01 * r.verify["path_mm"].get<double>());
  expectVerified(r, 0.99);
}

// The same branches on the robot. Where a split front enters a side branch, its first layer
// region is a sliver narrower than half a bead: it is printed as a centre line as wide as the
// sliver (left out before, the region above it stood two layers over the last printed one:
// supported 0.9897). Such a bead is narrower than it is tall; every print row extrudes.
TEST(GeodesicPipeline, BranchesOnRobotPrintTheirSlivers) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = branchesBytes();
  const Settings s = branchesSettings("robot6-ur5");
  const Sliced r = sliceAndVerify(bytes, "branches.stl", s);
  if (!r.out.ok()) return;
  expectConsistent(r);
  EXPECT_LT(r.report["geodesic"]["unfilled_regions"].get<int>(), 10) << r.report["geodesic"].dump();
  size_t prints = 0, dry = 0;
  std::istringstream rows(r.out.program);
  for (std::string row; std::getline(rows, row);) {
    if (row.empty() || row[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream cols(row);
    for (std::string c; std::getline(cols, c, ',');) f.push_back(c);
    ASSERT_EQ(f.size(), 9u) << row;
    if (f[8] != "print") continue;
    ++prints;
    if (!(std::stod(f[6]) > 0)) ++dry;
  }
  EXPECT_GT(prints, 10000u);
  EXPECT_EQ(dry, 0u) << "print rows that do not extrude";
  std::printf("branches robot6 verify %s\n", r.verify.dump().c_str());
  expectVerified(r, 0.99);
}

TEST(GeodesicPipeline, SequenceSettingIsFollowed) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeBox(-8, -8, 0, 8, 8, 12));
  Settings s = geodesicSettings("table5", 0.8);
  s.geodesic.targetTets = 4000;
  s.geodesic.heatTime = 1;  // the paper's field: the box's height within 5 % (12.6 mm at 30 h^2)
  s.geodesic.alignPasses = 0;
  s.geodesic.alignRetryPasses = 0;
  for (const char* seq : {"lpt", "dpt", "a3"}) {
    Settings c = s;
    ASSERT_TRUE(setSetting(c, "geodesic.sequence", seq).ok());
    SliceOutput out = runSlice(bytes.data(), bytes.size(), "box.stl", c);
    ASSERT_TRUE(out.ok()) << out.message;
    const Json g = Json::parse(out.reportJson)["geodesic"];
    std::string upper = seq;
    for (char& ch : upper) ch = static_cast<char>(std::toupper(ch));
    EXPECT_EQ(g["sequence"], upper);
    // A box has one IGDS per layer: every traversal is the same chain, no retraction.
    EXPECT_EQ(g["retractions"].get<int>(), 0) << g.dump();
    EXPECT_TRUE(g["collision_free"].get<bool>());
    EXPECT_NEAR(g["max_geodesic_mm"].get<double>(), 12.0, 0.6);
  }
}

TEST(GeodesicPipeline, RefusesBadSetUps) {
  const std::vector<uint8_t> box = test::binaryStl(test::makeBox(-8, -8, 0, 8, 8, 12));
  Settings s = geodesicSettings("table5", 0.8);
  s.geodesic.targetTets = 4000;
  {
    Settings c = s;
    c.machine = "cartesian3";
    EXPECT_EQ(runSlice(box.data(), box.size(), "box.stl", c).status, Status::InvalidOption);
  }
  {
    Settings c = s;
    EXPECT_FALSE(setSetting(c, "geodesic.sequence", "random").ok());
    EXPECT_FALSE(setSetting(c, "geodesic.nozzle_angle_deg", "95").ok());
    EXPECT_FALSE(setSetting(c, "geodesic.tet_size_mm", "-1").ok());
    ASSERT_TRUE(setSetting(c, "geodesic.tet_size_mm", "0.01").ok());  // far too many tets
    SliceOutput out = runSlice(box.data(), box.size(), "box.stl", c);
    // Refused before meshing by the memory budget, naming the setting.
    EXPECT_EQ(out.status, Status::OutOfMemory) << out.message;
    EXPECT_NE(out.message.find("geodesic.tet_size_mm"), std::string::npos) << out.message;
  }
  {
    // An open mesh is not a solid: refused with repair = none (auto closes it).
    Mesh open = test::makeBox(-8, -8, 0, 8, 8, 12);
    open.triangles.resize(open.triangles.size() - 3);
    const std::vector<uint8_t> bytes = test::binaryStl(open);
    Settings none = s;
    ASSERT_TRUE(setSetting(none, "repair", "none").ok());
    SliceOutput out = runSlice(bytes.data(), bytes.size(), "open.stl", none);
    EXPECT_EQ(out.status, Status::OpenMesh);
  }
  {
    // A truncated .tet file.
    const std::string tet = "8 vertices\n5 tets\n0 0 0\n1 0 0\n";
    const std::vector<uint8_t> bytes(tet.begin(), tet.end());
    SliceOutput out = runSlice(bytes.data(), bytes.size(), "cut.tet", s);
    EXPECT_EQ(out.status, Status::TruncatedFile) << out.message;
  }
}

TEST(GeodesicPipeline, CancelStopsInEveryStage) {
  const std::vector<uint8_t> box = test::binaryStl(test::makeBox(-8, -8, 0, 8, 8, 12));
  Settings s = geodesicSettings("table5", 0.8);
  s.geodesic.targetTets = 4000;
  std::set<std::string> seen;
  SliceOutput full = runSlice(box.data(), box.size(), "box.stl", s, [&](const char* stage, double) {
    seen.insert(stage);
    return true;
  });
  ASSERT_TRUE(full.ok()) << full.message;
  for (const char* stage : {"tetmesh", "field", "igds", "order", "paths", "toolpath"}) {
    EXPECT_TRUE(seen.count(stage)) << stage;
    SliceOutput out = runSlice(box.data(), box.size(), "box.stl", s, [&](const char* st, double) {
      return std::string(st) != stage;
    });
    EXPECT_EQ(out.status, Status::Cancelled) << stage;
  }
}

}  // namespace
}  // namespace omnislice
