// SPDX-License-Identifier: MIT
// The pipeline end to end (read -> prepare -> place -> slice -> plan -> G-code -> verify), on
// generated and real models, plus its error and cancellation paths.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "../test_meshes.h"
#include "../test_support.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

int countMarkers(const std::string& program, const std::string& marker) {
  int n = 0;
  for (size_t p = program.find(marker); p != std::string::npos; p = program.find(marker, p + 1)) ++n;
  return n;
}

Settings solidSettings() {
  Settings s;
  EXPECT_TRUE(setSetting(s, "infill", "100").ok());
  return s;
}

SliceOutput sliceBytes(const std::vector<uint8_t>& bytes, const std::string& name, const Settings& s) {
  return runSlice(bytes.data(), bytes.size(), name, s);
}

Json verifyBytes(const std::string& program, const std::vector<uint8_t>& bytes, const std::string& name) {
  VerifyOutput v = runVerify(program, bytes.data(), bytes.size(), name);
  EXPECT_TRUE(v.ok()) << v.message;
  return v.ok() ? Json::parse(v.verifyJson) : Json::object();
}

// A 20 x 10 x 6 mm box: exact layer count, report keys, G-code layer markers, verified print.
TEST(Pipeline, BoxSlicesAndVerifies) {
  const auto bytes = test::binaryStl(test::makeBox(0, 0, 0, 20, 10, 6));
  SliceOutput out = sliceBytes(bytes, "box.stl", solidSettings());
  ASSERT_TRUE(out.ok()) << out.message;
  const Json report = Json::parse(out.reportJson);
  for (const char* key : {"method", "machine", "layers", "path_mm", "extrusion_mm",
                          "estimated_time_s", "timings_ms"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  for (const char* stage : {"read", "validate", "place", "slice", "toolpath", "program", "total"}) {
    EXPECT_TRUE(report["timings_ms"].contains(stage)) << stage;
  }
  EXPECT_EQ(report["layers"].get<int>(), 30);  // 6 mm / 0.2 mm
  EXPECT_EQ(countMarkers(out.program, "; omnislice:layer "), 30);
  // Filament ~ solid volume / filament section (100 % infill): within 15 %.
  const double filamentSection = M_PI * 1.75 * 1.75 / 4;
  EXPECT_NEAR(report["extrusion_mm"].get<double>() * filamentSection, 20.0 * 10 * 6, 0.15 * 1200);
  // The placement in the header centres the box and keeps z >= 0.
  const Json info = Json::parse(out.infoJson);
  EXPECT_NEAR(info["placed_bbox"]["min"][0].get<double>(), -10, 1e-9);
  EXPECT_NEAR(info["placed_bbox"]["min"][2].get<double>(), 0, 1e-9);

  const Json v = verifyBytes(out.program, bytes, "box.stl");
  EXPECT_GE(v["inside"].get<double>(), 0.99) << v.dump();
  EXPECT_GE(v["coverage"].get<double>(), 0.95) << v.dump();
  EXPECT_EQ(v["collisions"].get<int>(), 0) << v.dump();
  EXPECT_EQ(v["limits"].get<int>(), 0) << v.dump();
  EXPECT_NEAR(v["extrusion_mm"].get<double>(), report["extrusion_mm"].get<double>(),
              1e-3 * report["extrusion_mm"].get<double>());
  EXPECT_EQ(v["layers"].get<int>(), 30);

  // Preview: one feature code per segment, 6 floats per segment, layers in range.
  ASSERT_EQ(out.preview.toolpath.positions.size(), 6 * out.preview.toolpath.features.size());
  ASSERT_EQ(out.preview.toolpath.layers.size(), out.preview.toolpath.features.size());
  for (uint32_t l : out.preview.toolpath.layers) ASSERT_LT(l, 30u);
}

// Slicing along a direction d on cartesian3 turns d up; the recorded placement maps the input
// onto the part frame, so verify against the input mesh succeeds for every direction.
TEST(Pipeline, DirectionsOtherThanZ) {
  const auto bytes = test::binaryStl(test::makeUvSphere(8, 32, 24));
  for (const char* d : {"0,0,1", "1,0,0", "1,1,1", "0,-1,0.3"}) {
    Settings s = solidSettings();
    ASSERT_TRUE(setSetting(s, "direction", d).ok());
    SliceOutput out = sliceBytes(bytes, "sphere.stl", s);
    ASSERT_TRUE(out.ok()) << d << ": " << out.message;
    const Json report = Json::parse(out.reportJson);
    // The placement's rotation takes d to +Z.
    Eigen::Matrix4d t;
    for (int i = 0; i < 16; ++i) t(i / 4, i % 4) = report["placement"][i].get<double>();
    Eigen::Vector3d dir(report["direction"][0], report["direction"][1], report["direction"][2]);
    EXPECT_NEAR((t.topLeftCorner<3, 3>() * dir - Eigen::Vector3d::UnitZ()).norm(), 0, 1e-9) << d;
    // A 16 mm sphere: 80 layers when the poles lie on d, a little fewer when the tessellation is
    // seen from another direction (its extent along d is then slightly under 16 mm).
    EXPECT_LE(report["layers"].get<int>(), 80) << d;
    EXPECT_GE(report["layers"].get<int>(), 78) << d;
    const Json v = verifyBytes(out.program, bytes, "sphere.stl");
    EXPECT_GE(v["inside"].get<double>(), 0.99) << d << " " << v.dump();
    EXPECT_GE(v["coverage"].get<double>(), 0.95) << d << " " << v.dump();
  }
}

// Real models from ../shared/models, scaled to 30 mm, along several directions.
TEST(Pipeline, RealModelsVerify) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  struct Case {
    const char* file;
    const char* up;
  };
  for (const Case& c : {Case{"compas_bunny_closed_low_res.obj", "z"}, Case{"pymdp_kitten.off", "y"},
                        Case{"compas_overhang_coin_closed_low_res.stl", "z"}}) {
    const auto bytes = test::readBytes(test::sharedModelsDir() / c.file);
    for (const char* d : {"0,0,1", "0.5,0,1"}) {
      Settings s = solidSettings();
      ASSERT_TRUE(setSetting(s, "fit_mm", "30").ok());
      ASSERT_TRUE(setSetting(s, "up", c.up).ok());
      ASSERT_TRUE(setSetting(s, "direction", d).ok());
      SliceOutput out = sliceBytes(bytes, c.file, s);
      ASSERT_TRUE(out.ok()) << c.file << ": " << out.message;
      const Json report = Json::parse(out.reportJson);
      EXPECT_EQ(report["open_chains"].get<int>(), 0) << c.file;
      EXPECT_EQ(countMarkers(out.program, "; omnislice:layer "), report["layers"].get<int>());
      const Json v = verifyBytes(out.program, bytes, c.file);
      EXPECT_GE(v["inside"].get<double>(), 0.99) << c.file << " d=" << d << " " << v.dump();
      EXPECT_GE(v["coverage"].get<double>(), 0.95) << c.file << " d=" << d << " " << v.dump();
      EXPECT_EQ(v["limits"].get<int>(), 0) << c.file;
    }
  }
}

// Each failure comes back as a status with a message, never a crash.
TEST(Pipeline, ErrorsAreStatuses) {
  Settings s;
  {  // empty input
    SliceOutput out = runSlice(nullptr, 0, "empty.stl", s);
    EXPECT_EQ(out.status, Status::EmptyInput);
    EXPECT_FALSE(out.message.empty());
  }
  {  // open mesh: a box without its top
    Mesh box = test::makeBox(0, 0, 0, 10, 10, 10);
    box.triangles.resize(box.triangles.size() - 0);
    box.triangles.erase(box.triangles.begin() + 6, box.triangles.begin() + 12);
    const auto bytes = test::binaryStl(box);
    Settings none = s;
    ASSERT_TRUE(setSetting(none, "repair", "none").ok());
    SliceOutput out = sliceBytes(bytes, "open.stl", none);
    EXPECT_EQ(out.status, Status::OpenMesh) << out.message;
    EXPECT_NE(out.message.find("repair"), std::string::npos) << out.message;
  }
  {  // model larger than the bed
    const auto bytes = test::binaryStl(test::makeBox(0, 0, 0, 500, 10, 10));
    SliceOutput out = sliceBytes(bytes, "big.stl", s);
    EXPECT_EQ(out.status, Status::InvalidOption);
    EXPECT_NE(out.message.find("bed"), std::string::npos) << out.message;
  }
  {  // inconsistent settings
    Settings bad;
    ASSERT_TRUE(setSetting(bad, "layer_height", "1.5").ok());
    const auto bytes = test::binaryStl(test::makeBox(0, 0, 0, 10, 10, 10));
    EXPECT_EQ(sliceBytes(bytes, "box.stl", bad).status, Status::InvalidOption);
  }
  {  // NaN vertex
    Mesh box = test::makeBox(0, 0, 0, 10, 10, 10);
    box.positions[4] = std::nan("");
    const auto bytes = test::binaryStl(box);
    EXPECT_EQ(sliceBytes(bytes, "nan.stl", s).status, Status::NonFiniteVertex);
  }
}

// Progress names the stages in order; returning false cancels at any stage.
TEST(Pipeline, ProgressAndCancel) {
  const auto bytes = test::binaryStl(test::makeUvSphere(10, 24, 16));
  Settings s;
  s.support.mode = SupportMode::None;  // the sphere's underside would add the supports stage
  std::vector<std::string> stages;
  SliceOutput out = runSlice(bytes.data(), bytes.size(), "s.stl", s, [&](const char* st, double f) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
    if (stages.empty() || stages.back() != st) stages.push_back(st);
    return true;
  });
  ASSERT_TRUE(out.ok()) << out.message;
  const std::vector<std::string> order = {"read",     "validate", "place", "slice",
                                          "toolpath", "motion",   "program"};
  std::vector<std::string> seen;
  for (const auto& st : stages) {
    if (seen.empty() || seen.back() != st) seen.push_back(st);
  }
  EXPECT_EQ(std::set<std::string>(seen.begin(), seen.end()),
            std::set<std::string>(order.begin(), order.end()));
  // First occurrence order follows the pipeline.
  size_t last = 0;
  for (const auto& st : order) {
    const size_t pos = std::find(seen.begin(), seen.end(), st) - seen.begin();
    EXPECT_GE(pos, last) << st;
    last = pos;
  }
  for (const auto& cancelAt : order) {
    SliceOutput c = runSlice(bytes.data(), bytes.size(), "s.stl", s,
                             [&](const char* st, double) { return cancelAt != st; });
    EXPECT_EQ(c.status, Status::Cancelled) << cancelAt;
    EXPECT_TRUE(c.program.empty());
  }
}

}  // namespace
}  // namespace omnislice
