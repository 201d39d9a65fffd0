// SPDX-License-Identifier: MIT
// Supports end to end (paper 000 Section V): the planar method with `support = projected` holds
// an overhang that prints unsupported without it; the multidir method's projected supports keep
// each part's support inside its subspace (never in a region printed later) and off the part, and
// bring verify's `supported` to >= 0.99 on the shared Kitten.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_meshes.h"
#include "geometry/aabb_tree.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"
#include "program/read_program.h"
#include "slice_and_verify.h"
#include "test_support.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;
using test::Sliced;
using test::sliceAndVerify;

struct SupportMoves {
  size_t count = 0;
  size_t insidePart = 0;     // end points deeper than w/2 inside the part
  size_t laterSubspace = 0;  // end points above the base plane of a part printed later
  size_t belowOwnBase = 0;   // end points below their own part's base plane
};

// Every support move of the program against the part and the parts' planes (from the report).
SupportMoves checkSupportMoves(const Sliced& r, double w) {
  SupportMoves s;
  const ParsedProgram p = readProgram(r.out.program);
  EXPECT_TRUE(p.ok()) << p.message;
  const AabbTree tree(r.out.partMesh);
  std::vector<std::pair<Eigen::Vector3d, double>> planes;  // by print index; platform part: none
  if (r.report.contains("multidir")) {
    for (const Json& part : r.report["multidir"]["parts"]) {
      if (part["plane"].is_null()) {
        planes.push_back({Eigen::Vector3d::Zero(), 0});
      } else {
        const Json& n = part["plane"]["normal"];
        planes.push_back({Eigen::Vector3d(n[0], n[1], n[2]), part["plane"]["offset_mm"].get<double>()});
      }
    }
  }
  for (const ProgramMove& m : p.moves) {
    // Extruding support moves (an unretract, E without motion, keeps the previous feature).
    if (p.featureOf(m) != "support" || !(m.filament > 0) || !((m.to - m.from).norm() > 1e-9)) continue;
    ++s.count;
    if (tree.inside(m.to) && tree.closest(m.to).distance > 0.5 * w + 1e-6) {
      ++s.insidePart;
      if (s.insidePart < 5) std::printf("inside %g %g %g part %d layer %d line %d\n", m.to.x(), m.to.y(), m.to.z(), m.part, m.layer, m.line);
    }
    for (size_t j = 0; j < planes.size(); ++j) {
      if (planes[j].first.isZero()) continue;
      const double h = planes[j].first.dot(m.to) - planes[j].second;
      if (int(j) > m.part && h > 0.5 * w) {
        ++s.laterSubspace;
        if (s.laterSubspace < 5) std::printf("later %g %g %g part %d plane %zu h %g line %d\n", m.to.x(), m.to.y(), m.to.z(), m.part, j, h, m.line);
      }
      if (int(j) == m.part && h < -1e-6) ++s.belowOwnBase;
    }
  }
  return s;
}

TEST(SupportPipeline, PlanarSupportsHoldTheOverhang) {
  const Mesh l = test::makeLBracket(10);
  const std::vector<uint8_t> bytes = test::binaryStl(l);
  Settings s;
  s.machine = "cartesian3";
  s.layerHeight = 0.2;  // 1.5 h below the solid line spacing: a bridge shows as unsupported
  s.support.mode = SupportMode::None;
  const Sliced none = sliceAndVerify(bytes, "l.stl", s);
  Settings with = s;
  ASSERT_TRUE(setSetting(with, "support", "projected").ok());
  const Sliced sup = sliceAndVerify(bytes, "l.stl", with);
  if (!none.out.ok() || !sup.out.ok()) return;
  std::printf("L planar: none %s\nprojected %s\nsupport %s\n", none.verify.dump().substr(0, 300).c_str(),
              sup.verify.dump().substr(0, 300).c_str(), sup.report["support"].dump().c_str());
  EXPECT_FALSE(none.report.contains("support"));
  EXPECT_LT(none.verify["supported"].get<double>(), 0.97);
  EXPECT_GE(sup.verify["supported"].get<double>(), 0.99);
  EXPECT_GE(sup.verify["inside"].get<double>(), 0.99);
  EXPECT_EQ(sup.verify["collisions"].get<int>(), 0);
  const Json& j = sup.report["support"];
  EXPECT_TRUE(j["generated"].get<bool>());
  // Every tree (samples less merges) reaches the platform.
  EXPECT_GT(j["merges"].get<size_t>(), 0u);
  EXPECT_EQ(j["landed_on_platform"].get<size_t>(), j["samples"].get<size_t>() - j["merges"].get<size_t>());
  EXPECT_NEAR(j["risky_area_mm2"].get<double>(), 200.0, 1e-6);
  // What was printed is what the regions hold (lines at the solid spacing fill them).
  const double printed = j["printed_volume_mm3"].get<double>(), region = j["region_volume_mm3"].get<double>();
  EXPECT_GT(printed, 0);
  EXPECT_NEAR(printed / region, 1.0, 0.15);
  const SupportMoves m = checkSupportMoves(sup, s.effectiveLineWidth());
  EXPECT_GT(m.count, 0u);
  EXPECT_EQ(m.insidePart, 0u);
}

// The paper's Kitten at 0.2 mm layers and 20 % infill on table5: with projected supports the
// program reaches supported >= 0.99 and never loses to the same decomposition without them.
// support = auto with the planar method decides by the share of the surface that overhangs: the
// L-bracket's arm underside (20 x 10 mm, facing straight down) against the bracket's whole surface
// summed here from its triangles; above support.auto_share_pct (1 %) it prints supports, and the
// program then holds (supported >= 0.99); a box (its bottom on the platform) gets none; with the
// threshold above the bracket's share, none either.
TEST(SupportPipeline, PlanarAutoDecidesByTheOverhangShare) {
  const Mesh l = test::makeLBracket(10);
  double area = 0;
  for (size_t f = 0; f < l.faceCount(); ++f) {
    const Eigen::Vector3d a = l.vertex(l.triangles[3 * f]), b = l.vertex(l.triangles[3 * f + 1]),
                          c = l.vertex(l.triangles[3 * f + 2]);
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  const std::vector<uint8_t> bytes = test::binaryStl(l);
  Settings s;
  s.layerHeight = 0.2;
  const Sliced r = sliceAndVerify(bytes, "l.stl", s);
  if (!r.out.ok()) return;
  const Json& a = r.report["support_auto"];
  EXPECT_NEAR(a["overhang_mm2"].get<double>(), 200, 1e-6);
  EXPECT_NEAR(a["overhang_percent"].get<double>(), 100 * 200 / area, 1e-6);
  EXPECT_EQ(a["chosen"], "projected");
  EXPECT_TRUE(r.report.contains("support"));
  EXPECT_GE(r.verify["supported"].get<double>(), 0.99);
  bool said = false;
  for (const Json& w : r.report["warnings"]) said |= w["code"] == "supports_added";
  EXPECT_TRUE(said) << "the report says why supports were added";

  Settings high = s;
  ASSERT_TRUE(setSetting(high, "support.auto_share_pct", std::to_string(100 * 200 / area + 1)).ok());
  const SliceOutput none = runSlice(bytes.data(), bytes.size(), "l.stl", high);
  ASSERT_TRUE(none.ok());
  const Json nr = Json::parse(none.reportJson);
  EXPECT_EQ(nr["support_auto"]["chosen"], "none");
  EXPECT_FALSE(nr.contains("support"));

  const std::vector<uint8_t> box = test::binaryStl(test::makeBox(0, 0, 0, 20, 10, 5));
  const SliceOutput b = runSlice(box.data(), box.size(), "box.stl", s);
  ASSERT_TRUE(b.ok());
  const Json br = Json::parse(b.reportJson);
  EXPECT_EQ(br["support_auto"]["overhang_mm2"].get<double>(), 0);
  EXPECT_EQ(br["support_auto"]["chosen"], "none");
}

TEST(SupportPipeline, KittenProjectedSupportsStayInTheirSubspaces) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / "pymdp_kitten.off");
  Settings s;
  s.method = Method::Multidir;
  s.machine = "table5";
  s.verify = VerifyMode::Warn;  // 1.4-1.7 % unsupported at cut-plane edges (issue 25 item 4)
  s.placement.up = UpAxis::PosY;
  s.placement.fitMm = 60;
  Settings none = s;
  ASSERT_TRUE(setSetting(none, "support", "none").ok());
  const Sliced with = sliceAndVerify(bytes, "kitten.off", s);
  const Sliced without = sliceAndVerify(bytes, "kitten.off", none);
  if (!with.out.ok() || !without.out.ok()) return;
  const Json& j = with.report["multidir"]["supports"];
  std::printf("kitten supports %s\nverify %s\nwithout %s\n", j.dump().c_str(), with.verify.dump().substr(0, 400).c_str(),
              without.verify.dump().substr(0, 400).c_str());
  EXPECT_TRUE(with.report["multidir"]["supports_generated"].get<bool>());
  EXPECT_FALSE(without.report["multidir"]["supports_generated"].get<bool>());
  EXPECT_GT(with.report["multidir"]["support_volume_mm3"].get<double>(), 0);
  EXPECT_EQ(without.report["multidir"]["support_volume_mm3"].get<double>(), 0);
  EXPECT_GT(j["samples"].get<size_t>(), 0u);
  EXPECT_GE(with.verify["supported"].get<double>(), 0.99);
  EXPECT_GE(with.verify["supported"].get<double>(), without.verify["supported"].get<double>());
  EXPECT_GE(with.verify["inside"].get<double>(), 0.99);
  EXPECT_EQ(with.verify["collisions"].get<int>(), 0);
  EXPECT_EQ(with.verify["limits"].get<int>(), 0);
  const SupportMoves m = checkSupportMoves(with, s.effectiveLineWidth());
  EXPECT_GT(m.count, 0u);
  EXPECT_EQ(m.insidePart, 0u);
  EXPECT_EQ(m.laterSubspace, 0u);
  EXPECT_EQ(m.belowOwnBase, 0u);
}

// Fertility (fit 60, flat base at min x) and the compas bunny on table5 with projected supports:
// most of what stayed unsupported was the first layer of a later part on a plane crossing the
// earlier part's layers at 80-120 degrees, where the beads of both sides touch yet lie w/2 + h/2
// (0.325 mm) apart, beyond the 1.5 h (0.3 mm) that holds a bead. With the earlier parts
// reaching across the planes (multidir.interface_overlap, default 1) both reach 0.99
// (without: Fertility 0.9881, bunny 0.9893), and the later parts' nozzles still clear them.
TEST(SupportPipeline, EarlierPartsReachAcrossSteepPlanes) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  struct Case {
    const char* file;
    UpAxis up;
  };
  for (const Case& c : {Case{"nestedcages_fertility.off", UpAxis::PosX}, Case{"compas_bunny_closed_low_res.obj", UpAxis::PosZ}}) {
    const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / c.file);
    Settings s;
    s.method = Method::Multidir;
    s.machine = "table5";
    s.verify = VerifyMode::Warn;  // short of supported >= 0.99 at cut-plane edges (issue 25 item 4)
    s.verifyAttempts = 1;         // the programs of these two settings, not a remedied one
    s.placement.up = c.up;
    s.placement.fitMm = 60;
    ASSERT_TRUE(setSetting(s, "support", "projected").ok());
    Settings flush = s;
    ASSERT_TRUE(setSetting(flush, "multidir.interface_overlap", "0").ok());
    const Sliced reach = sliceAndVerify(bytes, c.file, s);
    const Sliced cut = sliceAndVerify(bytes, c.file, flush);
    if (!reach.out.ok() || !cut.out.ok()) return;
    const double a = reach.verify["supported"].get<double>(), b = cut.verify["supported"].get<double>();
    std::printf("%s supported %.4f (flush at the planes %.4f)\n", c.file, a, b);
    EXPECT_GE(a, 0.99) << c.file;
    EXPECT_GT(a, b + 0.001) << c.file;
    EXPECT_EQ(reach.verify["collisions"].get<int>(), 0) << c.file;
    EXPECT_GE(reach.verify["inside"].get<double>(), 0.99) << c.file;
    // The same decomposition and part volumes: only the slicing reaches across.
    EXPECT_EQ(reach.report["multidir"]["parts"].size(), cut.report["multidir"]["parts"].size());
    EXPECT_EQ(reach.report["multidir"]["volume_mm3"], cut.report["multidir"]["volume_mm3"]);
  }
}

}  // namespace
}  // namespace omnislice
