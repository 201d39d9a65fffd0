// SPDX-License-Identifier: MIT
// The pipeline simulates what it made before writing it (issue 25: never a silently defective
// program): an unsound multi-axis program is refused with a statement of why and what would print
// the model, the report and the preview still say where; verify = warn delivers it with a
// warning; the figures are those of `omnislice verify` on the same program.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pipeline/pipeline.h"
#include "pipeline/pipeline_fixtures.h"
#include "pipeline/soundness.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

// A sphere resting on its pole, sliced by the voxel method on table5 with the thickness bound
// off (voxel.max_thickness_ratio = 0: the layers as paper 001 extracts them): where the layers
// fan out they are too thick for the beads above (measured: ~14 % of the surface unsupported;
// with the bound the same slice is sound, SoundVoxelSphereWithTheThicknessBound).
std::vector<uint8_t> sphereBytes() { return test::binaryStl(test::makeUvSphere(8, 32, 16, {0, 0, 8})); }

// A shared model's slice on table5 at fitMm.
Settings onTable5(Method method, double fitMm) {
  Settings s;
  s.method = method;
  s.machine = "table5";
  s.placement.fitMm = fitMm;
  return s;
}

Settings voxelOnTable() {
  Settings s;
  s.method = Method::Voxel;
  s.machine = "table5";
  s.voxel.maxThicknessRatio = 0;
  return s;
}

TEST(Soundness, UnsoundMultiAxisProgramIsRefusedWithAStatementAndTheFiguresStay) {
  const std::vector<uint8_t> bytes = sphereBytes();
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", voxelOnTable());
  ASSERT_EQ(out.status, Status::UnsoundProgram) << out.message;
  EXPECT_TRUE(out.program.empty()) << "a refused program is not delivered";
  EXPECT_EQ(out.message.rfind("the voxel method cannot print this model soundly on table5: ", 0), 0u) << out.message;
  EXPECT_NE(out.message.find("What would: "), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("--method multidir"), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("verify=warn"), std::string::npos) << out.message;
  // The report still says what was measured and why.
  const Json r = Json::parse(out.reportJson);
  const Json& v = r["verify"];
  EXPECT_EQ(v["mode"], "refuse");
  EXPECT_FALSE(v["sound"].get<bool>());
  ASSERT_FALSE(v["failures"].empty());
  EXPECT_LT(v["supported"].get<double>(), 0.99);
  EXPECT_EQ(v["statement"], out.message);
  // Where it fails: the unsupported tips lie on the part (within a bead of its box).
  const std::vector<float>& pts = out.preview.verify.unsupported;
  ASSERT_FALSE(pts.empty());
  ASSERT_EQ(pts.size() % 3, 0u);
  EXPECT_LE(pts.size() / 3, 4000u);
  for (size_t i = 0; i < pts.size(); i += 3) {
    const Eigen::Vector3d p(pts[i], pts[i + 1], pts[i + 2]);
    EXPECT_LT(std::abs(std::hypot(p.x(), p.y(), p.z() - 8) - 8), 1.0) << "unsupported tip off the sphere: " << p.transpose();
  }
}

TEST(Soundness, WarnDeliversTheSameProgramWithTheStatementAsAWarning) {
  const std::vector<uint8_t> bytes = sphereBytes();
  Settings s = voxelOnTable();
  s.verify = VerifyMode::Warn;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  ASSERT_FALSE(out.program.empty());
  bool warned = false;
  for (const Warning& w : out.warnings) warned = warned || (w.code == "unsound_program" && !w.message.empty());
  EXPECT_TRUE(warned);
  // The figures are `omnislice verify`'s on the delivered program (the same simulation, run
  // independently from the program text and the input bytes).
  const Json v = Json::parse(out.reportJson)["verify"];
  const VerifyOutput check = runVerify(out.program, bytes.data(), bytes.size(), "sphere.stl");
  ASSERT_TRUE(check.ok()) << check.message;
  const Json c = Json::parse(check.verifyJson);
  EXPECT_EQ(v["mode"], "warn");
  EXPECT_DOUBLE_EQ(v["supported"].get<double>(), c["supported"].get<double>());
  EXPECT_DOUBLE_EQ(v["inside"].get<double>(), c["inside"].get<double>());
  EXPECT_DOUBLE_EQ(v["coverage"].get<double>(), c["coverage"].get<double>());
  EXPECT_EQ(v["collisions"].get<size_t>(), c["collisions"].get<size_t>());
  EXPECT_EQ(v["samples"].get<size_t>(), c["samples"].get<size_t>());
}

TEST(Soundness, SoundProgramPassesAndOffSkipsTheSimulation) {
  // The L-bracket cut once by multidir on table5 prints soundly (measured supported 0.996).
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s;
  s.method = Method::Multidir;
  s.machine = "table5";
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const Json v = Json::parse(out.reportJson)["verify"];
  EXPECT_TRUE(v["sound"].get<bool>());
  EXPECT_TRUE(v["failures"].empty());
  EXPECT_EQ(v["statement"], "");
  EXPECT_EQ(v["collisions"].get<size_t>(), 0u);
  EXPECT_GE(v["supported"].get<double>(), 0.99);
  EXPECT_FALSE(v["coverage_judged"].get<bool>()) << "sparse infill is not judged by coverage";
  // verify = off: no simulation, no section; the planar method's auto is off.
  s.verify = VerifyMode::Off;
  const SliceOutput off = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  ASSERT_TRUE(off.ok());
  EXPECT_FALSE(Json::parse(off.reportJson).contains("verify"));
  EXPECT_EQ(off.program.size(), out.program.size());
  Settings planar;
  const SliceOutput p = runSlice(bytes.data(), bytes.size(), "l.stl", planar);
  ASSERT_TRUE(p.ok());
  EXPECT_FALSE(Json::parse(p.reportJson).contains("verify"));
}

TEST(Soundness, PlanarOnRequestNamesSupportsAsTheRemedy) {
  // The bracket's arm overhangs: planar without supports leaves it over air.
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s;
  s.verify = VerifyMode::Refuse;
  s.support.mode = SupportMode::None;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  ASSERT_EQ(out.status, Status::UnsoundProgram) << out.message;
  EXPECT_NE(out.message.find("printed over air"), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("support=projected"), std::string::npos) << out.message;
}

TEST(Soundness, SoundVoxelSphereWithTheThicknessBound) {
  const std::vector<uint8_t> bytes = sphereBytes();
  Settings s = voxelOnTable();
  s.voxel.maxThicknessRatio = Settings().voxel.maxThicknessRatio;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const Json r = Json::parse(out.reportJson);
  const Json& v = r["verify"];
  EXPECT_TRUE(v["sound"].get<bool>()) << v.dump();
  EXPECT_GE(v["supported"].get<double>(), 0.99);
  EXPECT_EQ(v["collisions"].get<int>(), 0);
  // The bound is what made it sound: partial layers were laid, and every layer's distance to the
  // layers below stays within 1.3 x the target layer plus a sample's slack (the top layers under
  // the pole's cap excepted: their foot falls past the sphere's last full layer; the worst, 0.49
  // mm, is 0.1 mm under the pole, in the seventh layer from the top).
  const Json& th = r["voxel"]["thickness"];
  EXPECT_GT(th["partial_layers"].get<int>(), 0);
  const double target = r["voxel"]["target_layer_mm"].get<double>();
  const std::vector<double> maxima = th["layer_max_mm"].get<std::vector<double>>();
  ASSERT_GT(maxima.size(), 10u);
  for (size_t l = 1; l + 8 < maxima.size(); ++l) EXPECT_LE(maxima[l], 1.3 * target * 1.1) << "layer " << l;
}

// The statement's remedy is true: a shared model at 20 mm on table5 is refused because its surface
// hangs; the statement names `key=value`, and with it the same slice is sound (one program per
// slice: the pipeline's own second attempts are off).
void expectRemedyMakesItSound(const char* file, Method method, const std::string& key, const std::string& value,
                              const std::vector<std::pair<std::string, std::string>>& start = {}) {
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(method, 20);
  s.verifyAttempts = 1;
  for (const auto& [k, v] : start) ASSERT_TRUE(setSetting(s, k, v).ok()) << k;
  const SliceOutput refused = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_EQ(refused.status, Status::UnsoundProgram) << refused.message;
  EXPECT_NE(refused.message.find("printed over air"), std::string::npos) << refused.message;
  ASSERT_NE(refused.message.find(key + "=" + value), std::string::npos) << refused.message;
  ASSERT_TRUE(setSetting(s, key, value).ok());
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(out.ok()) << out.message;
  const Json v = Json::parse(out.reportJson)["verify"];
  EXPECT_TRUE(v["sound"].get<bool>()) << v.dump();
  EXPECT_GE(v["supported"].get<double>(), 0.99);
  EXPECT_GT(v["supported"].get<double>(), Json::parse(refused.reportJson)["verify"]["supported"].get<double>());
}

// Geodesic on the shared coin with the field of the paper and surface steps of a whole interval
// (geodesic.align_passes 0, geodesic.max_thickness_ratio 1, the defaults before 10 and 0.7) and
// the ideal nozzle axes (motion.axis_freedom_deg 0; with the default 15 this coin is sound): the
// outer beads stand out where the field is slow at the surface (supported 0.990); thinner
// surface steps.
TEST(Soundness, GeodesicRemedyAppliedGivesASoundProgram) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  expectRemedyMakesItSound("compas_overhang_coin_closed_low_res.stl", Method::Geodesic, "geodesic.max_thickness_ratio", "0.7",
                           {{"geodesic.max_thickness_ratio", "1"}, {"geodesic.align_passes", "0"},
                            {"geodesic.align_retry_passes", "0"}, {"motion.axis_freedom_deg", "0"}});
}

// Multidir on the shared topopt (supports on): overhangs just under the paper's 45 deg hang
// (supported 0.987); a stricter self-supporting angle.
TEST(Soundness, MultidirRemedyAppliedGivesASoundProgram) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  expectRemedyMakesItSound("reinforcedfdm_topopt_new.tet", Method::Multidir, "multidir.alpha_max_deg", "40");
}

// The same slice of topopt (supported 0.988 at the default 0.45 mm lines on 0.2 mm layers): the
// statement's other lever, narrower lines (line_width <= 2.1 x layer_height), makes it sound too.
TEST(Soundness, MultidirNarrowerLinesGiveASoundProgram) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  expectRemedyMakesItSound("reinforcedfdm_topopt_new.tet", Method::Multidir, "line_width", "0.42");
}

// verify's figures of a slice on table5 that is written whatever the gate finds (verify = warn).
Json checkedFigures(const char* file, Method method, double fitMm, const std::vector<std::pair<std::string, std::string>>& set,
                    UpAxis up = UpAxis::PosZ) {
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(method, fitMm);
  s.placement.up = up;
  EXPECT_TRUE(setSetting(s, "verify", "warn").ok());
  for (const auto& [key, value] : set) EXPECT_TRUE(setSetting(s, key, value).ok()) << key;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), file, s);
  EXPECT_TRUE(out.ok()) << out.message;
  return out.ok() ? Json::parse(out.reportJson)["verify"] : Json::object();
}

// The voxel branches at 40 mm (voxel.smooth 5): every path point had a free axis, yet 6 samples
// collided, all on the first move of 2-3 point paths whose travel arrived with an axis that
// swept the cone through the material on the turn. The axes are now checked as the program moves
// them (the planner's filter, each move's turn) and such a turn is moved: no collision is left.
TEST(Soundness, VoxelTurnsBetweenFreeAxesDoNotCollide) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Json v = checkedFigures("compas_branches_70_closed_low_res.stl", Method::Voxel, 40, {{"voxel.smooth", "5"}});
  ASSERT_TRUE(v.contains("collisions")) << v.dump();
  EXPECT_EQ(v["collisions"].get<size_t>(), 0u) << v.dump();
}

// The kitten (genus 1) at 40 mm: where the fronts around its hole merge, the paper's field leaves
// layers meeting at sharp creases that no nozzle axis reaches (770 mm of tool path left out);
// aligning the heat's directions there (geodesic.align_passes, default 40) leaves none, and the
// program is sound.
TEST(Soundness, GeodesicAlignedFrontsLeaveNoToolPathOut) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  // The paper's field and its axes (no freedom for motion, so no path is retried near them).
  const Json paper = checkedFigures("pymdp_kitten.off", Method::Geodesic, 40,
                                    {{"geodesic.align_passes", "0"}, {"geodesic.align_retry_passes", "0"},
                                     {"motion.axis_freedom_deg", "0"}},
                                    UpAxis::PosY);
  const Json now = checkedFigures("pymdp_kitten.off", Method::Geodesic, 40, {}, UpAxis::PosY);
  ASSERT_TRUE(paper.contains("left_out_mm") && now.contains("left_out_mm"));
  EXPECT_GT(paper["left_out_mm"].get<double>(), 100.0) << paper.dump();
  EXPECT_LT(now["left_out_mm"].get<double>(), 1.0) << now.dump();
  EXPECT_TRUE(now["sound"].get<bool>()) << now.dump();
}

// The scenario the retry was measured on, before the defaults became 40 passes and axis freedom
// 25 (with which this kitten leaves nothing out at first): 10 passes, freedom 15, solid. The tool
// path's retry of left-out paths near their ideal axes (always on) still leaves more than 10 mm
// out there.
void setAsMeasured(Settings& s) {
  ASSERT_TRUE(setSetting(s, "geodesic.align_passes", "10").ok());
  ASSERT_TRUE(setSetting(s, "geodesic.align_retry_passes", "40").ok());
  ASSERT_TRUE(setSetting(s, "motion.axis_freedom_deg", "15").ok());
  ASSERT_TRUE(setSetting(s, "infill", "100").ok());  // as measured (sparse: 8.5 mm left out first)
}

// The kitten (ply, genus 1) at 20 mm, solid: ten alignment passes still leave 25 mm of tool path out;
// the second attempt with geodesic.align_retry_passes (40) leaves none and is kept, and
// the report says what the first left out. Without the retry the slice is refused.
TEST(Soundness, GeodesicRetryWithStrongerAlignmentLeavesNothingOut) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const char* file = "voxelmaam_kitten.ply";
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(Method::Geodesic, 20);
  ASSERT_TRUE(setSetting(s, "verify", "warn").ok());
  setAsMeasured(s);
  ASSERT_TRUE(setSetting(s, "geodesic.align_retry_passes", "0").ok());
  const SliceOutput once = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(once.ok()) << once.message;
  const Json a = Json::parse(once.reportJson);
  const double firstLeftOut = a["verify"]["left_out_mm"].get<double>();
  EXPECT_GT(firstLeftOut, 10.0) << a["verify"].dump();
  EXPECT_FALSE(a["geodesic"]["align_retry"]["retried"].get<bool>());

  s.geodesic.alignRetryPasses = 40;
  const SliceOutput twice = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(twice.ok()) << twice.message;
  const Json b = Json::parse(twice.reportJson);
  const Json& retry = b["geodesic"]["align_retry"];
  EXPECT_TRUE(retry["retried"].get<bool>()) << retry.dump();
  EXPECT_NEAR(retry["first_left_out_mm"].get<double>(), firstLeftOut, 1e-9);
  EXPECT_EQ(b["geodesic"]["align_passes"].get<double>(), 40);
  EXPECT_EQ(b["verify"]["left_out_mm"].get<double>(), 0.0);
  EXPECT_TRUE(b["verify"]["sound"].get<bool>()) << b["verify"].dump();
  for (const Warning& w : twice.warnings) EXPECT_NE(w.code, "skipped_tool_path") << w.message;
}

// The same retry with the second attempt beside the first (threads = 2, natively): the same
// program and report (timings aside) as one after another.
TEST(Soundness, GeodesicRetryBesideTheFirstMakesTheSameProgram) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const char* file = "voxelmaam_kitten.ply";
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(Method::Geodesic, 20);
  ASSERT_TRUE(setSetting(s, "verify", "warn").ok());
  setAsMeasured(s);
  s.threads = 1;
  const SliceOutput one = runSlice(bytes.data(), bytes.size(), file, s);
  s.threads = 2;
  const SliceOutput two = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(one.ok() && two.ok()) << one.message << two.message;
  const Json a = Json::parse(one.reportJson), b = Json::parse(two.reportJson);
  EXPECT_TRUE(b["geodesic"]["align_retry"]["retried"].get<bool>());
  EXPECT_EQ(one.program.substr(one.program.find('\n')), two.program.substr(two.program.find('\n')));
  EXPECT_EQ(test::timelessReport(a), test::timelessReport(b));
}

// The kitten (ply) on robot6 at 20 mm, geodesic: the program of the default settings leaves
// 1.2 % of the surface over air (supported 0.988); the pipeline makes it again with thinner
// layers at the surface (geodesic.max_thickness_ratio 0.55), finds that one sound and delivers
// it, saying so. With verify_attempts = 1 the slice is refused as before.
TEST(Soundness, UnsoundProgramIsMadeAgainWithARemedyAndTheSoundOneDelivered) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const char* file = "voxelmaam_kitten.ply";
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(Method::Geodesic, 20);
  s.machine = "robot6-ur5";
  s.verifyAttempts = 1;
  const SliceOutput once = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_EQ(once.status, Status::UnsoundProgram) << once.message;
  EXPECT_NE(once.message.find("printed over air"), std::string::npos) << once.message;
  EXPECT_TRUE(Json::parse(once.reportJson)["verify"]["attempts"].empty());

  s.verifyAttempts = Settings().verifyAttempts;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(out.ok()) << out.message;
  ASSERT_FALSE(out.program.empty());
  const Json r = Json::parse(out.reportJson);
  const Json& v = r["verify"];
  EXPECT_TRUE(v["sound"].get<bool>()) << v.dump();
  ASSERT_EQ(v["attempts"].size(), 1u) << v.dump();
  EXPECT_EQ(v["attempts"][0]["settings"], "geodesic.max_thickness_ratio=0.55");
  EXPECT_TRUE(v["attempts"][0]["sound"].get<bool>());
  EXPECT_EQ(r["geodesic"]["max_thickness_ratio"].get<double>(), 0.55) << "the report is the delivered program's";
  EXPECT_NE(out.program.find("geodesic.max_thickness_ratio = 0.55"), std::string::npos)
      << "the header lists the settings the program was made with";
  bool remedied = false;
  for (const Warning& w : out.warnings) {
    remedied = remedied || (w.code == "remedied" && w.message.find("printed over air") != std::string::npos);
  }
  EXPECT_TRUE(remedied);
  bool retries = false;
  for (const auto& t : out.report.timingsMs) retries = retries || t.first == "retries";
  EXPECT_TRUE(retries);
  // The delivered program, verified on its own.
  const VerifyOutput check = runVerify(out.program, bytes.data(), bytes.size(), file);
  ASSERT_TRUE(check.ok()) << check.message;
  const Json c = Json::parse(check.verifyJson);
  EXPECT_GE(c["supported"].get<double>(), 0.99) << check.verifyJson;
  EXPECT_EQ(c["collisions"].get<size_t>(), 0u);
}

TEST(Soundness, AutomaticRemediesFollowTheFailures) {
  VerifySection v;
  v.minSupported = 0.99;
  v.supported = 1;
  Settings s;
  s.method = Method::Voxel;
  EXPECT_TRUE(automaticRemedies(v, s).empty()) << "sound: nothing to remedy";
  v.collisions = 3;
  std::vector<SettingRemedy> r = automaticRemedies(v, s);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].key + "=" + r[0].value, "voxel.smooth=10");
  EXPECT_EQ(r[1].key + "=" + r[1].value, "voxel.strategy=sp-gcfa");
  {
    Settings other = s;
    other.voxel.strategy = GrowthStrategy::Gcfa;
    EXPECT_EQ(automaticRemedies(v, other).size(), 1u) << "another growth the user chose stays";
  }
  for (const SettingRemedy& x : r) {
    Settings t = s;
    EXPECT_TRUE(setSetting(t, x.key, x.value).ok()) << x.key;
  }
  s.method = Method::Geodesic;
  s.axisFreedomDegrees = 15;  // the freedom's own remedy: below
  EXPECT_TRUE(automaticRemedies(v, s).empty()) << "geodesic collisions: no setting the slicer changes";
  v.collisions = 0;
  v.supported = 0.985;
  r = automaticRemedies(v, s);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].value, "0.55");
  EXPECT_EQ(r[1].value, "0.45");
  s.geodesic.maxThicknessRatio = 0.5;
  r = automaticRemedies(v, s);
  ASSERT_EQ(r.size(), 1u) << "only ratios below the user's";
  EXPECT_EQ(r[0].value, "0.45");
  // Another failure besides the one a remedy addresses: nothing is tried.
  VerifySection both = v;
  both.leftOutMm = 22;
  EXPECT_TRUE(automaticRemedies(both, s).empty()) << "beads over air and tool path left out";
  // Tool path left out alone: the heat source within one layer of the platform (the interval,
  // layer_height when geodesic.interval_mm is 0); not when the user set the band.
  // Next to the bed only (the lowest left-out point within 5 intervals of the platform).
  both.supported = 1;
  EXPECT_TRUE(automaticRemedies(both, s).empty()) << "where it is left out unknown";
  r = automaticRemedies(both, s, 0.4);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].key + "=" + r[0].value, "geodesic.base_band_mm=0.2");
  EXPECT_TRUE(automaticRemedies(both, s, 2.0).empty()) << "left out 2 mm up (10 intervals)";
  s.geodesic.intervalMm = 0.6;
  EXPECT_EQ(automaticRemedies(both, s, 2.0).at(0).value, "0.6");
  s.geodesic.baseBandMm = 0.3;
  EXPECT_TRUE(automaticRemedies(both, s, 0.4).empty()) << "the band is the user's";
  s.geodesic = Settings().geodesic;
  both.collisions = 2;
  EXPECT_TRUE(automaticRemedies(both, s, 0.4).empty()) << "tool path left out and collisions";
  both = v;
  both.collisions = 0;
  both.surfaceReached = 0.5;
  both.minReached = 0.99;
  EXPECT_TRUE(automaticRemedies(both, s).empty()) << "beads over air and part of the surface not printed";
  s.method = Method::Voxel;
  both = v;
  both.collisions = 3;
  r = automaticRemedies(both, s);
  ASSERT_EQ(r.size(), 1u) << "collisions and beads over air: only another growth";
  EXPECT_EQ(r[0].key + "=" + r[0].value, "voxel.strategy=sp-gcfa");
  s.method = Method::Multidir;
  r = automaticRemedies(v, s);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].key + "=" + r[0].value, "multidir.alpha_max_deg=40");
  s.multidir.alphaMaxDeg = 40;
  EXPECT_TRUE(automaticRemedies(v, s).empty()) << "already that strict";
  s.multidir.alphaMaxDeg = 45;
  s.support.mode = SupportMode::None;
  EXPECT_TRUE(automaticRemedies(v, s).empty()) << "without supports the statement sends to support=auto";
  s.method = Method::Planar;
  EXPECT_TRUE(automaticRemedies(v, s).empty());
  // Geodesic axes leaning further than 15 deg for motion (its default 25, or set): back to 15,
  // for collisions or tool path left out; not at 15 or below. Not voxel (as sound at 25 as at 15
  // where measured; its collisions have remedies of their own).
  s = Settings();
  both = v;
  both.supported = 1;
  both.collisions = 3;
  s.method = Method::Geodesic;
  for (double freedom : {-1.0, 25.0}) {
    s.axisFreedomDegrees = freedom;
    r = automaticRemedies(both, s);
    ASSERT_EQ(r.size(), 1u) << "geodesic collisions: no other setting";
    EXPECT_EQ(r[0].key + "=" + r[0].value, "motion.axis_freedom_deg=15");
    Settings t = s;
    EXPECT_TRUE(setSetting(t, r[0].key, r[0].value).ok());
  }
  s.method = Method::Voxel;
  r = automaticRemedies(both, s);
  ASSERT_EQ(r.size(), 2u) << "voxel.smooth and voxel.strategy only";
  EXPECT_EQ(r[0].key, "voxel.smooth");
  both.collisions = 0;
  both.leftOutMm = 5;
  s.method = Method::Geodesic;
  EXPECT_EQ(automaticRemedies(both, s).at(0).value, "15");
  s.axisFreedomDegrees = 15;
  EXPECT_TRUE(automaticRemedies(both, s).empty()) << "left out 5 mm, lowest point unknown, freedom 15";
}

// The branches at 20 mm, geodesic: the mesher's tets (0.31 mm cells) fill 55 % of the thin
// branches, so the layers reach 5 of 18 mm and the program prints 3 layers of 38. Coverage has no
// interior point in a part this thin, so the slice was judged sound; the share of the surface a
// bead comes near (31.5 %) refuses it now, and the statement names a tet size to try.
TEST(Soundness, GeodesicPartTheLayersDoNotReachIsRefused) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const char* file = "compas_branches_70_closed_low_res.stl";
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(Method::Geodesic, 20);
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_EQ(out.status, Status::UnsoundProgram) << out.message;
  EXPECT_NE(out.message.find("of the part's surface has no bead within"), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("geodesic.tet_size_mm=0.16"), std::string::npos) << out.message;
  const Json v = Json::parse(out.reportJson)["verify"];
  EXPECT_FALSE(v["coverage_judged"].get<bool>()) << v.dump();
  EXPECT_LT(v["surface_reached"].get<double>(), 0.5) << v.dump();
  // The same figure on a program that lays beads all over the part: the voxel branches (0.992).
  s.method = Method::Voxel;
  const SliceOutput voxel = runSlice(bytes.data(), bytes.size(), file, s);
  const Json vv = Json::parse(voxel.reportJson)["verify"];
  EXPECT_GE(vv["surface_reached"].get<double>(), 0.99) << vv.dump();
}

// The tool path's count of points it could not clear is conservative (a cone 3 deg wider, points as
// 0.25 mm balls): the ply kitten at 20 mm, voxel, leaves 246 such points and the simulation finds
// no collision. The nozzle_collision warning, which said they print touching the part, then goes
// (it contradicted the sound verdict); with verify off it stays.
TEST(Soundness, NozzleCollisionWarningDroppedWhereTheSimulationFindsNone) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const char* file = "voxelmaam_kitten.ply";
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / file);
  Settings s = onTable5(Method::Voxel, 20);
  const SliceOutput checked = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(checked.ok()) << checked.message;
  const Json r = Json::parse(checked.reportJson);
  ASSERT_GT(r["voxel"]["gouging_uncorrected"].get<size_t>(), 0u) << "no conservative count left: pick another case";
  EXPECT_EQ(r["verify"]["collisions"].get<size_t>(), 0u);
  for (const Warning& w : checked.warnings) EXPECT_NE(w.code, "nozzle_collision") << w.message;
  ASSERT_TRUE(setSetting(s, "verify", "off").ok());
  const SliceOutput unchecked = runSlice(bytes.data(), bytes.size(), file, s);
  ASSERT_TRUE(unchecked.ok()) << unchecked.message;
  bool warned = false;
  for (const Warning& w : unchecked.warnings) warned = warned || w.code == "nozzle_collision";
  EXPECT_TRUE(warned);
}

TEST(Soundness, CliWritesTheReportButNoProgramWhenRefused) {
  const std::filesystem::path dir = test::tempDir() / "soundness";
  std::filesystem::create_directories(dir);
  const std::filesystem::path stl = dir / "sphere.stl", prog = dir / "sphere.gcode", rep = dir / "sphere.json",
                              err = dir / "stderr.txt";
  const std::vector<uint8_t> bytes = sphereBytes();
  std::ofstream(stl, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  std::filesystem::remove(prog);
  std::filesystem::remove(rep);
  const std::string cmd = std::string(OMNISLICE_CLI_PATH) + " slice " + stl.string() + " -o " + prog.string() +
                          " --method voxel --machine table5 --set voxel.max_thickness_ratio=0 --report " + rep.string() + " 2>" + err.string();
  const int rc = std::system(cmd.c_str());
  EXPECT_NE(rc, 0);
  EXPECT_FALSE(std::filesystem::exists(prog));
  ASSERT_TRUE(std::filesystem::exists(rep));
  const Json r = Json::parse(std::ifstream(rep));
  EXPECT_FALSE(r["verify"]["sound"].get<bool>());
  std::ifstream e(err);
  const std::string text((std::istreambuf_iterator<char>(e)), {});
  EXPECT_NE(text.find("error: unsound_program: the voxel method cannot print"), std::string::npos) << text;
}

}  // namespace
}  // namespace omnislice
