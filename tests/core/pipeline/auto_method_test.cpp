// SPDX-License-Identifier: MIT
// method = auto (issue 28 item 1), through the pipeline:
//   - every method the machine takes runs, cheapest first (cartesian3: planar alone; table5:
//     planar, multidir, geodesic, voxel), each reported with its figures;
//   - the program delivered is byte for byte the chosen method's own (run alone with verify =
//     warn), apart from the date line;
//   - no other candidate beats it by the stated order (sound, then support within a tie of 1 % of
//     the laid material, then time), and one stopped before its check could not have;
//   - cancelling stops it.
#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../test_meshes.h"
#include "pipeline/auto_choice.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

// The program without its first line (the date it was made).
std::string undated(const std::string& program) { return program.substr(program.find('\n') + 1); }

SliceOutput alone(const std::vector<uint8_t>& bytes, Settings s, const std::string& method) {
  EXPECT_TRUE(setSetting(s, "method", method).ok());
  s.verify = VerifyMode::Warn;
  return runSlice(bytes.data(), bytes.size(), "l.stl", s);
}

TEST(AutoMethod, Cartesian3HasOnePlanarCandidate) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s;
  s.method = Method::Auto;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const Json r = Json::parse(out.reportJson);
  EXPECT_EQ(r["method"], "planar");
  ASSERT_EQ(r["auto"]["candidates"].size(), 1u);
  EXPECT_EQ(r["auto"]["candidates"][0]["method"], "planar");
  EXPECT_EQ(r["auto"]["chosen"], "planar");
  const SliceOutput planar = alone(bytes, s, "planar");
  ASSERT_TRUE(planar.ok());
  EXPECT_EQ(undated(out.program), undated(planar.program));
}

TEST(AutoMethod, Table5DeliversTheBestVerifiedProgram) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s = test::coarseCurvedSettings(Method::Auto);
  s.verify = VerifyMode::Auto;
  s.threads = 1;  // one after another: candidates that cannot win stop early
  std::vector<std::string> stages;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s, [&](const std::string& st, double) {
    if (stages.empty() || stages.back() != st) stages.push_back(st);
    return true;
  });
  ASSERT_TRUE(out.ok()) << out.message;
  const Json r = Json::parse(out.reportJson);
  const Json& a = r["auto"];
  std::vector<std::string> methods;
  for (const Json& c : a["candidates"]) methods.push_back(c["method"]);
  EXPECT_EQ(methods, (std::vector<std::string>{"planar", "multidir", "geodesic", "voxel"}));
  const std::string chosen = a["chosen"];
  EXPECT_EQ(r["method"], chosen);
  EXPECT_EQ(a["reason"].get<std::string>().rfind(chosen + ":", 0), 0u) << a["reason"];
  EXPECT_TRUE(r["verify"]["sound"].get<bool>()) << a["reason"];
  std::printf("auto on the L bracket: %s\n", a["reason"].get<std::string>().c_str());
  EXPECT_NE(std::find(stages.begin(), stages.end(), "auto"), stages.end());

  // The chosen method alone makes the same program.
  const SliceOutput own = alone(bytes, s, chosen);
  ASSERT_TRUE(own.ok()) << own.message;
  EXPECT_EQ(undated(out.program), undated(own.program));

  // Nothing beats it by the stated order.
  const double support = r["support_volume_mm3"], time = r["estimated_time_s"];
  const double laid = r["extrusion_mm"].get<double>() * 3.14159265358979 / 4 * s.filamentDiameter * s.filamentDiameter;
  const double tie = std::max(1.0, 0.01 * laid);
  for (const Json& c : a["candidates"]) {
    if (c["method"] == chosen) continue;
    SCOPED_TRACE(c.dump());
    const double cs = c["support_volume_mm3"], ct = c["estimated_time_s"];
    if (c["stopped_early"].get<bool>()) {
      // It could have been sound at best: then it loses on support, or on time at equal support.
      EXPECT_TRUE(cs > support + tie || (cs >= support - tie && ct >= time));
      EXPECT_TRUE(c["verify"].is_null());
      continue;
    }
    if (c["status"] != "ok") continue;
    if (!c["verify"]["sound"].get<bool>()) continue;
    EXPECT_FALSE(cs < support - tie) << "a sound candidate with less support";
    if (std::abs(cs - support) <= tie) {
      EXPECT_GE(ct, time) << "as little support, and faster";
    }
  }
}

// In threads every candidate is checked (none stops early: that would depend on which finished
// first) and the same program is delivered as one after another.
TEST(AutoMethod, ThreadsDeliverTheSameProgram) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s = test::coarseCurvedSettings(Method::Auto);
  s.threads = 1;
  const SliceOutput one = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  s.threads = 3;
  const SliceOutput three = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  ASSERT_TRUE(one.ok() && three.ok()) << one.message << three.message;
  EXPECT_EQ(undated(one.program), undated(three.program));
  const Json a1 = Json::parse(one.reportJson)["auto"], a3 = Json::parse(three.reportJson)["auto"];
  EXPECT_EQ(a1["chosen"], a3["chosen"]);
  ASSERT_EQ(a1["candidates"].size(), a3["candidates"].size());
  for (size_t k = 0; k < a3["candidates"].size(); ++k) {
    const Json& c1 = a1["candidates"][k];
    const Json& c3 = a3["candidates"][k];
    EXPECT_EQ(c1["method"], c3["method"]);
    EXPECT_FALSE(c3["stopped_early"].get<bool>()) << c3.dump();
    // A candidate that ran to the end in both gives the same figures.
    if (!c1["stopped_early"].get<bool>()) {
      EXPECT_EQ(c1["verify"], c3["verify"]) << c1["method"];
    }
    EXPECT_EQ(c1["estimated_time_s"], c3["estimated_time_s"]) << c1["method"];
  }
}

TEST(AutoMethod, Cancels) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s = test::coarseCurvedSettings(Method::Auto);
  // Cancelled while the second candidate runs: no program, whatever the first made.
  bool second = false;
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s, [&](const std::string& stage, double f) {
    if (stage == "auto" && f > 0) second = true;
    return !(second && stage == "toolpath");
  });
  EXPECT_TRUE(second);
  EXPECT_EQ(out.status, Status::Cancelled);
  EXPECT_TRUE(out.program.empty());
}

// The page's pool (workers/auto-pool.js) slices each candidate of planAuto on its own and asks
// chooseAuto: it delivers the program and the auto section that runAuto delivers in threads.
TEST(AutoMethod, PoolPlanAndChoiceMatchThreads) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s = test::coarseCurvedSettings(Method::Auto);
  s.threads = 2;
  const SliceOutput threads = runSlice(bytes.data(), bytes.size(), "l.stl", s);
  ASSERT_TRUE(threads.ok()) << threads.message;

  Outcome o;
  const Json plan = Json::parse(planAuto(bytes.data(), bytes.size(), "l.stl", s, &o));
  ASSERT_TRUE(o.ok()) << o.message;
  std::vector<SliceOutput> outs;
  std::vector<Json> cands;
  auto slice = [&](size_t k, const Json& changes, bool full) {
    Settings c = s;
    for (const auto& [key, value] : changes.items()) EXPECT_TRUE(setSetting(c, key, value.get<std::string>()).ok());
    outs[k] = runSlice(bytes.data(), bytes.size(), "l.stl", c);
    cands[k] = {{"method", plan["candidates"][k]["method"]},
                {"status", statusCode(outs[k].status)},
                {"message", outs[k].message},
                {"ms", 1.0},
                {"full", full},
                {"report", outs[k].ok() ? Json::parse(outs[k].reportJson) : Json()}};
  };
  outs.resize(plan["candidates"].size());
  cands.resize(outs.size());
  for (size_t k = 0; k < outs.size(); ++k) {
    ASSERT_EQ(plan["candidates"][k]["settings"]["verify_attempts"], "1");
    slice(k, plan["candidates"][k]["settings"], false);
  }
  Json d;
  for (int rounds = 0;; ++rounds) {
    ASSERT_LT(rounds, 10);
    std::vector<std::string> texts;
    for (const Json& c : cands) texts.push_back(c.dump());
    d = Json::parse(chooseAuto(s, texts, &o));
    ASSERT_TRUE(o.ok()) << o.message;
    if (!d.contains("rerun")) break;
    const size_t k = d["rerun"];
    Json changes = plan["candidates"][k]["settings"];
    changes.update(plan["rerun_settings"]);
    slice(k, changes, true);
  }
  ASSERT_EQ(d["status"], "ok") << d.dump();
  const size_t chosen = d["chosen"];
  EXPECT_EQ(undated(outs[chosen].program), undated(threads.program));
  Json a = d["auto"], at = Json::parse(threads.reportJson)["auto"];
  for (Json* x : {&a, &at}) {
    for (Json& c : (*x)["candidates"]) c.erase("timings_ms");
  }
  EXPECT_EQ(a, at);

  // A candidate JSON that is not one is refused with a message.
  chooseAuto(s, {"{\"method\": 3"}, &o);
  EXPECT_EQ(o.status, Status::InvalidOption);
  EXPECT_FALSE(o.message.empty());
}

// The choice on figures alone: an unsound candidate made with one attempt is made again only
// while it could still win; a sound one with less support wins over a faster one with more.
TEST(AutoMethod, DecisionOnFigures) {
  Settings s;
  s.verifyAttempts = 3;
  auto fig = [](const char* m, bool sound, double support, double time, bool full) {
    AutoFigures f;
    f.method = m;
    f.full = full;
    VerifySection v;
    v.sound = sound;
    v.supported = sound ? 0.995 : 0.9;
    v.minSupported = 0.99;
    f.verify = v;
    f.supportVolumeMm3 = support;
    f.estimatedTimeS = time;
    f.extrusionMm = 100;  // 240 mm^3 laid (1.75 mm filament): the tie is 2.4 mm^3
    return f;
  };
  // planar sound with 500 mm^3 of support; multidir unsound with 0: it could win, make it again.
  std::vector<AutoFigures> c = {fig("planar", true, 500, 1000, false), fig("multidir", false, 0, 2000, false)};
  EXPECT_EQ(decideAuto(c, s).rerun, 1);
  // Made again and still unsound: planar is chosen.
  c[1].full = true;
  AutoDecision d = decideAuto(c, s);
  EXPECT_EQ(d.rerun, -1);
  EXPECT_EQ(d.chosen, 0);
  EXPECT_EQ(d.section.chosen, "planar");
  // An unsound one that loses on support anyway is not made again.
  c = {fig("planar", true, 500, 1000, false), fig("voxel", false, 600, 3000, false)};
  EXPECT_EQ(decideAuto(c, s).rerun, -1);
  // Sound ones: less support wins over less time; within the tie, less time wins.
  c = {fig("planar", true, 500, 1000, true), fig("multidir", true, 0, 2000, true), fig("geodesic", true, 0.5, 1500, true)};
  d = decideAuto(c, s);
  EXPECT_EQ(d.section.chosen, "geodesic");
  EXPECT_EQ(d.section.candidates.size(), 3u);
  // None made a program: the first failure's code.
  AutoFigures f1;
  f1.method = "planar";
  f1.status = "open_mesh";
  f1.message = "open";
  d = decideAuto({f1}, s);
  EXPECT_EQ(d.chosen, -1);
  EXPECT_EQ(d.status, Status::OpenMesh);
}

}  // namespace
}  // namespace omnislice
