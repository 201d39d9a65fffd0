// SPDX-License-Identifier: MIT
#include "program/write_gcode.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "machine/machine_json.h"
#include "test_toolpaths.h"

namespace omnislice {
namespace {

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

ProgramInfo testInfo() {
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.machine = cartesian3Profile({220, 220, 250}, 0.4);
  info.layerHeight = 0.2;
  info.lineWidth = 0.45;
  info.settings = {{"layer_height", "0.2"}, {"line_width", "0"}, {"walls", "2"}, {"infill", "100"}};
  return info;
}

Toolpath smallBox() {
  test::BoxPathOptions o;
  o.half = 3;
  o.height = 1;
  return test::boxToolpath(o);
}

TEST(WriteGcode, MachineProfileAndJson) {
  const MachineProfile m = cartesian3Profile({220, 200, 250}, 0.6);
  EXPECT_EQ(m.kind, MachineKind::Cartesian3);
  EXPECT_EQ(m.axisLimits.at("X"), std::make_pair(-110.0, 110.0));
  EXPECT_EQ(m.axisLimits.at("Y"), std::make_pair(-100.0, 100.0));
  EXPECT_EQ(m.axisLimits.at("Z"), std::make_pair(0.0, 250.0));
  EXPECT_EQ(m.nozzle.diameter, 0.6);
  const std::string j = machineJson(m);
  EXPECT_EQ(j.find('\n'), std::string::npos);
  EXPECT_EQ(j,
            "{\"kind\":\"cartesian3\",\"axis_limits\":{\"X\":[-110.0,110.0],\"Y\":[-100.0,100.0],"
            "\"Z\":[0.0,250.0]},\"nozzle\":{\"diameter\":0.6,\"cone_half_angle_deg\":40.0,"
            "\"cone_length\":25.0}}");
  const MachineParseResult back = machineFromJson(j);
  ASSERT_TRUE(back.ok()) << back.message;
  EXPECT_EQ(back.machine.kind, m.kind);
  EXPECT_EQ(back.machine.axisLimits, m.axisLimits);
  EXPECT_EQ(back.machine.nozzle.diameter, 0.6);
  EXPECT_EQ(back.machine.nozzle.coneLength, 25);
  EXPECT_EQ(machineFromJson("{\"kind\":\"cartesian3\",\"axis_limits\":{\"X\":[5,1]}}").status,
            Status::ParseError);
  EXPECT_EQ(machineFromJson("{\"kind\":").status, Status::ParseError);
}

TEST(WriteGcode, HeaderLinesFollowTheFormatPage) {
  const Toolpath tp = smallBox();
  ProgramInfo info = testInfo();
  info.placement(0, 3) = 12.5;
  info.placement(2, 2) = -1;
  const WriteProgramResult r = writeGcode(tp, info);
  ASSERT_TRUE(r.ok()) << r.message;
  const auto lines = splitLines(r.text);
  ASSERT_GT(lines.size(), 20u);
  EXPECT_EQ(lines[0], std::string("; omnislice ") + OMNISLICE_VERSION + " planar 2026-11-21T12:00:00Z");
  EXPECT_EQ(lines[1], "; omnislice:machine " + machineJson(info.machine));
  EXPECT_EQ(lines[2], "; omnislice:placement [1,0,0,12.5,0,1,0,0,0,0,-1,0,0,0,0,1]");
  EXPECT_EQ(lines[3], "; omnislice:extrusion {\"mode\":\"absolute\",\"filament_diameter\":1.75}");
  EXPECT_EQ(lines[4], "; omnislice:feed {\"semantics\":\"xyz\"}");
  EXPECT_EQ(lines[5], "; omnislice:setting layer_height = 0.2");
  EXPECT_EQ(lines[6], "; omnislice:setting line_width = 0.45");
  EXPECT_EQ(lines[7], "; omnislice:setting nozzle_diameter = 0.4");
  EXPECT_EQ(lines[8], "; omnislice:setting filament_diameter = 1.75");
  // Remaining user settings follow; the duplicates of the four resolved ones are left out.
  EXPECT_EQ(lines[9], "; omnislice:setting walls = 2");
  EXPECT_EQ(lines[10], "; omnislice:setting infill = 100");
  EXPECT_TRUE(std::regex_match(lines[11], std::regex(
      R"(; estimated printing time \(normal mode\) = (\d+h )?(\d+m )?\d+s)"))) << lines[11];
  char filament[64];
  std::snprintf(filament, sizeof filament, "; filament used [mm] = %.2f", r.filamentMm);
  EXPECT_EQ(lines[12], filament);
  // Every header value is finite text.
  for (size_t i = 0; i < 13; ++i) {
    EXPECT_FALSE(std::regex_search(lines[i], std::regex(R"(\b(nan|inf)\b)", std::regex::icase)))
        << lines[i];
  }
  const nlohmann::json machine = nlohmann::json::parse(lines[1].substr(20));
  EXPECT_EQ(machine["kind"], "cartesian3");
}

TEST(WriteGcode, TimeAndFilamentEqualToolpathStats) {
  const Toolpath tp = smallBox();
  ProgramInfo info = testInfo();
  info.acceleration = 800;
  const WriteProgramResult r = writeGcode(tp, info);
  ASSERT_TRUE(r.ok());
  const ToolpathStats s = toolpathStats(tp, 800);
  // Through planMachineMotion: the same terms, summed in another order.
  EXPECT_NEAR(r.estimatedTimeS, s.estimatedTimeS, 1e-9 * s.estimatedTimeS);
  EXPECT_DOUBLE_EQ(r.filamentMm, s.filamentMm);
  EXPECT_GT(r.estimatedTimeS, 0);
  EXPECT_EQ(r.layers, 5);
  // The human line states the same time, rounded to seconds.
  const long total = std::lround(s.estimatedTimeS);
  std::string expect = std::to_string(total % 60) + "s";
  if (total >= 60) expect = std::to_string((total % 3600) / 60) + "m " + expect;
  if (total >= 3600) expect = std::to_string(total / 3600) + "h " + expect;
  EXPECT_NE(r.text.find("; estimated printing time (normal mode) = " + expect + "\n"),
            std::string::npos)
      << expect;
}

TEST(WriteGcode, StartEndCodeMovesAndMarkers) {
  const Toolpath tp = smallBox();
  const WriteProgramResult r = writeGcode(tp, testInfo());
  ASSERT_TRUE(r.ok());
  const auto lines = splitLines(r.text);
  auto find = [&](const std::string& prefix, size_t from = 0) {
    for (size_t i = from; i < lines.size(); ++i) {
      if (lines[i].rfind(prefix, 0) == 0) return i;
    }
    return lines.size();
  };
  const size_t g21 = find("G21"), g90 = find("G90"), m82 = find("M82"), m140 = find("M140 S60"),
               m104 = find("M104 S210"), m190 = find("M190 S60"), m109 = find("M109 S210"),
               g28 = find("G28"), g92 = find("G92 E0"), firstMove = find("G1 X");
  EXPECT_LT(g21, g90);
  EXPECT_LT(g90, m82);
  EXPECT_LT(m82, m140);
  EXPECT_LT(m140, m190);
  EXPECT_LT(m104, m109);
  EXPECT_LT(m109, g28);
  EXPECT_LT(g28, g92);
  EXPECT_LT(g92, firstMove);
  EXPECT_EQ(lines[lines.size() - 3], "M104 S0");
  EXPECT_EQ(lines[lines.size() - 2], "M140 S0");
  EXPECT_EQ(lines[lines.size() - 1], "M84");

  // Move lines: G0 for travel with X Y Z, G1 for print with E; F only when it changes; E absolute
  // (never decreasing on printing lines); 3 decimals for coordinates and 5 for E.
  const std::regex move(R"((G[01])( X-?\d+\.\d{3} Y-?\d+\.\d{3} Z-?\d+\.\d{3})?( E-?\d+\.\d{5})?( F[\d.]+)?)");
  double lastF = -1, lastE = -1e9;
  int layerMarkers = 0, featureMarkers = 0, typeLines = 0;
  size_t moveLines = 0;
  for (size_t i = g92 + 1; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l.rfind("; omnislice:layer ", 0) == 0) ++layerMarkers;
    if (l.rfind("; omnislice:feature ", 0) == 0) ++featureMarkers;
    if (l.rfind(";TYPE:", 0) == 0) ++typeLines;
    if (l[0] != 'G') continue;
    std::smatch m;
    ASSERT_TRUE(std::regex_match(l, m, move)) << l;
    ++moveLines;
    if (m[1] == "G0") {
      EXPECT_FALSE(m[3].matched) << l;
    }
    if (m[4].matched) {
      const double f = std::stod(m[4].str().substr(2));
      EXPECT_NE(f, lastF) << "F repeated: " << l;
      lastF = f;
    }
    if (m[1] == "G1" && m[2].matched && m[3].matched) {
      const double e = std::stod(m[3].str().substr(2));
      EXPECT_GE(e, lastE) << l;
      lastE = e;
    }
  }
  EXPECT_GE(moveLines, tp.moves.size());
  EXPECT_EQ(layerMarkers, 5);
  EXPECT_EQ(featureMarkers, typeLines);
  EXPECT_EQ(featureMarkers, 5 * 3);  // wall-outer, wall-inner, infill on each layer

  // No heating lines when the temperatures are 0.
  ProgramInfo cold = testInfo();
  cold.nozzleTemperature = 0;
  cold.bedTemperature = 0;
  const WriteProgramResult c = writeGcode(tp, cold);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c.text.find("M109"), std::string::npos);
  EXPECT_EQ(c.text.find("M190"), std::string::npos);
}

// Part cooling fan: off (M107) in the start code and for the first fanOffLayers layers, then M106
// at fanPercent of 255, at bridgeFanPercent while bridges print, back after; M107 at the end.
// Read back line by line, every extruding move carries the fan its layer and feature ask for.
TEST(WriteGcode, FanOffOnTheFirstLayersThenOnAndFasterOverBridges) {
  Toolpath tp = smallBox();
  for (Move& m : tp.moves) {
    if (m.layer == 3 && m.feature == Feature::Infill) m.feature = Feature::Bridge;
  }
  ProgramInfo info = testInfo();
  info.fanPercent = 50;
  info.bridgeFanPercent = 100;
  info.fanOffLayers = 2;
  const WriteProgramResult r = writeGcode(tp, info);
  ASSERT_TRUE(r.ok()) << r.message;
  const auto lines = splitLines(r.text);
  int fan = -1, layer = -1, changes = 0;
  std::string feature;
  size_t extruding = 0;
  bool sawBridge = false;
  for (const std::string& l : lines) {
    if (l == "M107" || l.rfind("M107 ", 0) == 0) {
      fan = 0;
      ++changes;
    } else if (l.rfind("M106 S", 0) == 0) {
      fan = std::stoi(l.substr(6));
      ++changes;
    } else if (l.rfind("; omnislice:layer ", 0) == 0) {
      layer = std::stoi(l.substr(18));
    } else if (l.rfind("; omnislice:feature ", 0) == 0) {
      feature = l.substr(20);
    } else if (l.rfind("G1 X", 0) == 0 && l.find(" E") != std::string::npos) {
      ++extruding;
      const int want = layer < 2 ? 0 : feature == "bridge" ? 255 : 128;
      ASSERT_EQ(fan, want) << "layer " << layer << " " << feature << ": " << l;
      sawBridge = sawBridge || feature == "bridge";
    }
  }
  EXPECT_TRUE(sawBridge);
  EXPECT_GT(extruding, 100u);
  EXPECT_EQ(fan, 0);  // switched off at the end
  // Start off, on at layer 2, bridge up and back down on layer 3, off at the end.
  EXPECT_EQ(changes, 5);
  // The fan lines change nothing a replay measures: same program without them.
  ProgramInfo still = info;
  still.fanPercent = 0;
  still.bridgeFanPercent = 0;
  const WriteProgramResult q = writeGcode(tp, still);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q.text.find("M106"), std::string::npos);
  std::string stripped;
  for (const std::string& l : lines) {
    if (l != "M107" && l.rfind("M106 ", 0) != 0) stripped += l + "\n";
  }
  EXPECT_EQ(stripped, q.text) << "only the fan lines differ";
  ProgramInfo bad = testInfo();
  bad.fanPercent = 150;
  EXPECT_EQ(writeGcode(tp, bad).status, Status::InvalidOption);
  bad = testInfo();
  bad.fanOffLayers = -1;
  EXPECT_EQ(writeGcode(tp, bad).status, Status::InvalidOption);
}

TEST(WriteGcode, RejectsWhatCartesian3CannotPrint) {
  Toolpath tp = smallBox();
  ProgramInfo info = testInfo();
  info.machine.kind = MachineKind::Table5;
  EXPECT_EQ(writeGcode(tp, info).status, Status::InvalidOption);

  info = testInfo();
  Toolpath tilted = tp;
  for (Move& m : tilted.moves) {
    if (m.kind == MoveKind::Print) {
      m.axis = Eigen::Vector3d(0, 1, 1).normalized();
      break;
    }
  }
  const WriteProgramResult r = writeGcode(tilted, info);
  EXPECT_EQ(r.status, Status::InvalidOption);
  EXPECT_NE(r.message.find("+Z"), std::string::npos);
  EXPECT_TRUE(r.text.empty());

  Toolpath nan = tp;
  nan.moves[3].position.x() = std::nan("");
  EXPECT_EQ(writeGcode(nan, info).status, Status::InvalidOption);
  info.layerHeight = 0;
  EXPECT_EQ(writeGcode(tp, info).status, Status::InvalidOption);
}

}  // namespace
}  // namespace omnislice
