// SPDX-License-Identifier: MIT
// Issue 33: the estimated time is what the program itself asks of the machine. A G-code program
// is read back (program/read_program) and its time recomputed from its own words, apart from the
// planner: each line's duration is its axis distance over its F (the header's feed semantics:
// "xyz" = the linear distance, or the rotary one for a purely rotary move; "combined" = both), an
// extrusion-only line its filament over F, and the tip is ramped as a firmware look-ahead does
// (its own implementation here, from the header's `acceleration` and `junction_deviation`: the
// part-frame chord of each line cruised at chord / duration, junction speeds from the angle
// between consecutive chords, a stop at each line that does not move the tip, a backward and a
// forward pass, trapezoids). The sum is within 5 % of the report's estimated_time_s, and no line
// moves a rotary axis faster than the machine declares. Also planar programs (cartesian3), where
// the ramps are most of the difference from a from-rest estimate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "../test_meshes.h"
#include "../test_support.h"
#include "machine/machine.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"
#include "program/read_program.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

struct Replay {
  double seconds = 0;
  double worstRotaryRatio = 0;  // largest |rotary axis rate| / its declared velocity
  size_t lines = 0;
};

Replay replayTime(const std::string& program) {
  Replay out;
  const ParsedProgram p = readProgram(program);
  EXPECT_TRUE(p.ok()) << p.message;
  if (!p.ok() || p.moves.empty()) return out;
  std::smatch m;
  double accel = 0, jd = -1;
  if (std::regex_search(program, m, std::regex("; omnislice:setting acceleration = ([0-9.eE+-]+)"))) accel = std::stod(m[1]);
  if (std::regex_search(program, m, std::regex("; omnislice:setting junction_deviation = ([0-9.eE+-]+)"))) jd = std::stod(m[1]);
  EXPECT_GT(accel, 0) << "the header lists the acceleration";
  EXPECT_GE(jd, 0) << "the header lists the junction deviation";
  // Per counted line: the tip's chord (direction, length) and its cruise; then the look-ahead.
  struct Line {
    Eigen::Vector3d dir{0, 0, 0};
    double length = 0, cruise = 0, fixed = 0;  // fixed: a line without tip motion, its own time
  };
  std::vector<Line> lines;
  const bool combined = p.feedSemantics == "combined";
  EXPECT_TRUE(combined || p.feedSemantics == "xyz") << p.feedSemantics;
  const size_t n = p.moves.front().axes.size();
  const std::vector<std::string> names = machineAxisNames(p.machine.kind);
  // The first line moves from home (every value 0 after G28) to the park pose, where the plan
  // and its estimate start: its rates are checked, its time is not counted.
  std::vector<double> prev(n, 0.0);
  size_t i = 0;
  while (i < p.moves.size()) {
    // One source line: its pieces (an interpolated rotary move) share the line and the feed.
    size_t j = i;
    double lin2 = 0, rot2 = 0, tip = 0, filament = 0;
    std::vector<double> delta(n, 0);
    const std::vector<double> start = prev;
    while (j < p.moves.size() && p.moves[j].line == p.moves[i].line) {
      filament += p.moves[j].filament;
      prev.assign(p.moves[j].axes.begin(), p.moves[j].axes.end());
      ++j;
    }
    // The tip's chord in the part frame (a turning move's tip path bends; the ramp is the tip's).
    tip = (p.moves[j - 1].to - p.moves[i].from).norm();
    for (size_t k = 0; k < n; ++k) {
      delta[k] = prev[k] - start[k];
      (k < 3 ? lin2 : rot2) += delta[k] * delta[k];
    }
    const double feed = p.moves[i].feedMmPerMin / 60.0;
    const double d = combined ? std::sqrt(lin2 + rot2) : lin2 > 0 ? std::sqrt(lin2) : std::sqrt(rot2);
    double t = 0;
    if (feed > 0) t = d > 0 ? d / feed : std::abs(filament) / feed;
    if (i > 0) {
      Line l;
      if (tip > 0 && t > 0) {
        l.dir = (p.moves[j - 1].to - p.moves[i].from) / tip;
        l.length = tip;
        l.cruise = tip / t;
      } else {
        l.fixed = t;
      }
      lines.push_back(l);
      ++out.lines;
    }
    if (t > 0) {
      for (size_t k = 3; k < n; ++k) {
        const auto dyn = p.machine.axisDynamics.find(names[k]);
        if (dyn == p.machine.axisDynamics.end() || !(dyn->second.velocity > 0)) continue;
        // The written words are rounded (5 decimals of a degree): a short line's rate carries that.
        const double rate = std::max(0.0, std::abs(delta[k]) - 2e-5) / t;
        out.worstRotaryRatio = std::max(out.worstRotaryRatio, rate / dyn->second.velocity);
      }
    }
    i = j;
  }
  // The look-ahead: junction limits, backward and forward passes, trapezoids between them.
  const size_t n2 = lines.size();
  std::vector<double> v(n2 + 1, 0.0);  // v[k]: speed entering line k
  for (size_t k = 1; k < n2; ++k) {
    if (lines[k].length == 0 || lines[k - 1].length == 0) continue;
    const double c = -lines[k - 1].dir.dot(lines[k].dir);
    double lim = std::min(lines[k].cruise, lines[k - 1].cruise);
    if (c > 0.999999 || jd == 0) lim = 0;
    else if (c > -0.999999) lim = std::min(lim, std::sqrt(accel * jd * std::sqrt(0.5 * (1 - c)) / (1 - std::sqrt(0.5 * (1 - c)))));
    v[k] = lim;
  }
  for (size_t k = n2; k-- > 0;) {
    if (lines[k].length > 0) v[k] = std::min(v[k], std::sqrt(v[k + 1] * v[k + 1] + 2 * accel * lines[k].length));
  }
  for (size_t k = 0; k < n2; ++k) {
    if (lines[k].length > 0) v[k + 1] = std::min(v[k + 1], std::sqrt(v[k] * v[k] + 2 * accel * lines[k].length));
  }
  for (size_t k = 0; k < n2; ++k) {
    const Line& l = lines[k];
    if (l.length == 0) {
      out.seconds += l.fixed;
      continue;
    }
    const double vi = v[k], vo = k + 1 < n2 && lines[k + 1].length > 0 ? v[k + 1] : 0.0, vc = l.cruise;
    const double up = (vc * vc - vi * vi) / (2 * accel), down = (vc * vc - vo * vo) / (2 * accel);
    if (up + down <= l.length) {
      out.seconds += (vc - vi) / accel + (vc - vo) / accel + (l.length - up - down) / vc;
    } else {
      const double peak = std::sqrt(accel * l.length + 0.5 * (vi * vi + vo * vo));
      out.seconds += (peak - vi) / accel + (peak - vo) / accel;
    }
  }
  return out;
}

void expectReplayedTime(Method method, const char* what) {
  const Mesh sphere = test::makeUvSphere(10, 48, 24, Eigen::Vector3d(0, 0, 10));
  const std::vector<uint8_t> bytes = test::binaryStl(sphere);
  const Settings s = test::coarseCurvedSettings(method);
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const Json report = Json::parse(out.reportJson);
  const double planned = report["estimated_time_s"].get<double>();
  const Replay r = replayTime(out.program);
  std::printf("%s: replayed %.1f s over %zu lines, report %.1f s; fastest rotary axis at %.3f of its limit\n", what,
              r.seconds, r.lines, planned, r.worstRotaryRatio);
  ASSERT_GT(planned, 0);
  EXPECT_NEAR(r.seconds, planned, 0.05 * planned);
  EXPECT_LE(r.worstRotaryRatio, 1.01);
}

TEST(TimeReplay, VoxelProgramOnTable5) { expectReplayedTime(Method::Voxel, "voxel"); }
TEST(TimeReplay, GeodesicProgramOnTable5) { expectReplayedTime(Method::Geodesic, "geodesic"); }
TEST(TimeReplay, MultidirProgramOnTable5) { expectReplayedTime(Method::Multidir, "multidir"); }

// A planar print on cartesian3: a fine sphere's walls are many short moves that the firmware
// runs through without stopping; the estimate is the look-ahead's, well below moves from rest.
TEST(TimeReplay, PlanarProgramOnCartesian3) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeUvSphere(15, 96, 48, Eigen::Vector3d(0, 0, 15)));
  Settings s;
  ASSERT_TRUE(setSetting(s, "machine", "cartesian3").ok());
  const SliceOutput out = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  ASSERT_TRUE(setSetting(s, "junction_deviation", "0").ok());
  const SliceOutput stops = runSlice(bytes.data(), bytes.size(), "sphere.stl", s);
  ASSERT_TRUE(stops.ok()) << stops.message;
  const double planned = Json::parse(out.reportJson)["estimated_time_s"].get<double>();
  const double fromRest = Json::parse(stops.reportJson)["estimated_time_s"].get<double>();
  const Replay r = replayTime(out.program), rs = replayTime(stops.program);
  std::printf("planar: replayed %.1f s over %zu lines, report %.1f s; every move from rest %.1f s (replayed %.1f s)\n",
              r.seconds, r.lines, planned, fromRest, rs.seconds);
  EXPECT_NEAR(r.seconds, planned, 0.05 * planned);
  EXPECT_NEAR(rs.seconds, fromRest, 0.05 * fromRest);
  EXPECT_LT(planned, 0.95 * fromRest);
}

}  // namespace
}  // namespace omnislice
